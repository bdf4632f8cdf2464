// What a scenario will cost, and the budget the loader holds it to: the bundled modules fit
// with room to spare; each way a valid-looking file used to ask for more memory than a run
// has (a day-long time limit, a 0.05 mm grid with a 20 mm margin, a million-particle block, a
// three-spacing bond radius) is refused with the file, the line, the JSON path, the figure and
// the limit.
#include "scenarios/scenario_cost.hpp"

#include <gtest/gtest.h>

#include "scenarios/scenario_loader.hpp"
#include "tests/scenarios/scenario_test_support.hpp"

namespace acdr {
namespace {

using test::replace_once;

std::string module_text(const char* name) {
  return test::read_text(test::source_path(std::string("scenarios/modules/") + name));
}

/// The single error of loading `text`, as a string; "" when it loads.
std::string only_error(const std::string& text) {
  const LoadResult r = load_scenario_text(text, "m.json");
  if (r.ok()) return "";
  std::string out;
  for (const ScenarioError& e : r.errors) out += e.to_string() + "\n";
  EXPECT_EQ(r.errors.size(), 1u) << out;
  return r.errors.front().to_string();
}

/// The error at `path` of loading `text`, as a string; "" when there is none.
std::string error_at(const std::string& text, const std::string& path) {
  const LoadResult r = load_scenario_text(text, "m.json");
  for (const ScenarioError& e : r.errors) {
    if (e.json_path == path) return e.to_string();
  }
  ADD_FAILURE() << "no error at " << path << ":\n" << to_string(r.errors);
  return "";
}

TEST(ScenarioCost, LatticeNeighboursWithinTheBondRadius) {
  EXPECT_EQ(lattice_neighbours_within(1.0), 0);   // strictly closer than one spacing: none
  EXPECT_EQ(lattice_neighbours_within(1.5), 18);  // faces and edges
  EXPECT_EQ(lattice_neighbours_within(1.8), 26);  // and corners
  EXPECT_EQ(lattice_neighbours_within(3.0), 92);
}

TEST(ScenarioCost, BundledModulesFitTheBudgetWithRoomToSpare) {
  for (const char* name : {"01_box_warmup.json", "02_c4c5_healthy.json", "03_c4c5_degenerated.json",
                           "04_full_discectomy.json"}) {
    SCOPED_TRACE(name);
    const LoadResult r = load_scenario_file(test::source_path(std::string("scenarios/modules/") + name));
    ASSERT_TRUE(r.ok()) << to_string(r.errors);
    const ScenarioCost c = estimate_cost(*r.model);
    EXPECT_GT(c.particles, 100.0);
    EXPECT_GT(c.bonds, c.particles);
    EXPECT_LT(c.particles, ScenarioBudget::kParticles / 4);
    EXPECT_LT(c.bonds, ScenarioBudget::kBonds / 4);
    EXPECT_LT(c.grid_cells, ScenarioBudget::kGridCells / 4);
    EXPECT_EQ(c.recording_frames, r.model->time_limit_s / r.model->world.solver.dt_s);
    EXPECT_LT(c.bytes, ScenarioBudget::kBytes / 2);
  }
}

TEST(ScenarioCost, ADayLongTimeLimitIsRefusedAtTheTimeLimit) {
  const std::string text = replace_once(module_text("01_box_warmup.json"), "\"time_limit_s\": 60", "\"time_limit_s\": 86400");
  EXPECT_EQ(only_error(text),
            "m.json:" + std::to_string(test::line_of(text, "\"time_limit_s\"")) +
                ": /time_limit_s: recording too long (got 86400000 frames: 86400 s at a 1 ms step, expected at "
                "most 1000000; shorten time_limit_s or lengthen the step)");
  // 1000 s at 1 ms is the most a recording holds.
  EXPECT_EQ(only_error(replace_once(module_text("01_box_warmup.json"), "\"time_limit_s\": 60", "\"time_limit_s\": 1000")), "");
}

TEST(ScenarioCost, AFineWideGridIsRefusedAtItsSpacing) {
  const std::string text = replace_once(module_text("02_c4c5_healthy.json"), "\"sdf\": { \"spacing_mm\": 0.25 }",
                                        "\"sdf\": { \"spacing_mm\": 0.05, \"margin_mm\": 20 }");
  const std::string e = error_at(text, "/world/anatomy/sdf/spacing_mm");
  EXPECT_EQ(e.rfind("m.json:" + std::to_string(test::line_of(text, "\"sdf\"")) +
                        ": /world/anatomy/sdf/spacing_mm: distance grids too large (got about ", 0), 0u) << e;
  EXPECT_NE(e.find(" samples at spacing 0.05 mm and zone_spacing 0.5 mm over the grid region and a margin of 20 mm, "
                   "expected at most 20000000; use a coarser spacing, a smaller margin or a smaller region)"),
            std::string::npos) << e;
}

TEST(ScenarioCost, AMillionParticleBlockIsRefusedAtTheBlocks) {
  // 100 x 100 x 100 lattice sites at 0.1 mm: exactly 1,000,000 particles.
  std::string text = module_text("01_box_warmup.json");
  text = replace_once(text, "\"spacing_mm\": 2", "\"spacing_mm\": 0.1");
  text = replace_once(text, "{ \"min_mm\": [-15, -10, 0], \"max_mm\": [15, 10, 8]",
                      "{ \"min_mm\": [-5, -5, 0], \"max_mm\": [4.95, 4.95, 9.95]");
  const std::string e = error_at(text, "/world/nucleus/blocks");
  EXPECT_NE(e.find(": /world/nucleus/blocks: too many particles (got about 1000000 at spacing 0.1 mm, expected at "
                   "most 300000; use a larger spacing or smaller blocks)"),
            std::string::npos) << e;
}

TEST(ScenarioCost, AWideBondRadiusIsRefusedAtItsKey) {
  std::string text = module_text("01_box_warmup.json");
  text = replace_once(text, "\"spacing_mm\": 2", "\"spacing_mm\": 0.2");
  text = replace_once(text, "\"bond_radius_factor\": 1.5", "\"bond_radius_factor\": 3");
  const std::string e = error_at(text, "/world/nucleus/bond_radius_factor");
  EXPECT_NE(e.find("too many bonds (got about "), std::string::npos) << e;
  EXPECT_NE(e.find(" particles with 92 lattice neighbours each within 3 spacings, expected at most 10000000; "
                   "use a smaller bond_radius_factor or fewer particles)"),
            std::string::npos) << e;
}

TEST(ScenarioCost, FiguresEachWithinTheirLimitsCanStillBeTooMuchTogether) {
  // 63^3 = 250,047 particles with 28 bonds each (56 neighbours within 2.3 spacings), recorded
  // for the whole cap (no time limit).
  std::string text = module_text("01_box_warmup.json");
  text = replace_once(text, "\"time_limit_s\": 60", "\"time_limit_s\": 0");
  text = replace_once(text, "\"spacing_mm\": 2", "\"spacing_mm\": 0.1");
  text = replace_once(text, "\"bond_radius_factor\": 1.5", "\"bond_radius_factor\": 2.3");
  text = replace_once(text, "{ \"min_mm\": [-15, -10, 0], \"max_mm\": [15, 10, 8]",
                      "{ \"min_mm\": [-3, -3, 0], \"max_mm\": [3.25, 3.25, 6.25]");
  const std::string e = only_error(text);
  EXPECT_NE(e.find(": /world: estimated memory too large (got 3."), std::string::npos) << e;
  EXPECT_NE(e.find(" GB for 250047 particles, 7001316 bonds, 0 grid samples and 1000000 frames, expected at most 3.00 GB)"),
            std::string::npos) << e;
}

TEST(ScenarioCost, NoTimeLimitCostsTheWholeRecordingCap) {
  std::string text = replace_once(module_text("01_box_warmup.json"), "\"time_limit_s\": 60", "\"time_limit_s\": 0");
  const LoadResult r = load_scenario_text(text, "m.json");
  ASSERT_TRUE(r.ok()) << to_string(r.errors);
  EXPECT_EQ(estimate_cost(*r.model).recording_frames, ScenarioBudget::kRecordingFrames);
  EXPECT_EQ(kMaxRecordingFrames, 1000000u);
}

TEST(ScenarioCost, SummaryAndBytesRead) {
  ScenarioCost c;
  c.particles = 1200;
  c.bonds = 10800;
  c.grid_cells = 5;
  c.recording_frames = 60000;
  c.bytes = 4.5e8;
  EXPECT_EQ(cost_summary(c), "about 1200 particles, 10800 bonds, 5 grid samples, 60000 frames, 450 MB");
  EXPECT_EQ(format_bytes(2.5e9), "2.50 GB");
  EXPECT_EQ(format_bytes(12e3), "12 kB");
}

}  // namespace
}  // namespace acdr
