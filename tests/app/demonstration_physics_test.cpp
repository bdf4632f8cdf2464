// The C4-C5 modules' demonstrations were replayed with today's physics: each module's
// physics_check.json (written by scripts/demonstrations with results.json) holds the state hash
// the module reached replaying the first seconds of expert_1.csv, and the same seconds replayed
// now must reach it. A change of the nucleus, the bone or the instrument that moves the
// state fails here until the demonstrations are replayed and the rubrics calibrated again, so
// results.json and the shipped benchmarks cannot silently describe other physics.
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "app/attempt_session.hpp"
#include "engine/core/state_hash.hpp"
#include "scenarios/content_hash.hpp"
#include "tests/db/db_test_support.hpp"
#include "tests/scenarios/scenario_test_support.hpp"

namespace acdr {
namespace {

/// The trajectory's comments, header and samples up to `until_s`, line for line (the lines
/// scripts/demonstrations keeps for the check).
std::string first_seconds(const std::string& csv, double until_s) {
  std::istringstream in(csv);
  std::string line, out;
  while (std::getline(in, line)) {
    const bool sample = !line.empty() && line[0] != '#' && line.rfind("t_s", 0) != 0;
    if (sample && !(std::stod(line) <= until_s)) continue;
    out += line + "\n";
  }
  return out;
}

class DemonstrationPhysics : public ::testing::TestWithParam<const char*> {};

TEST_P(DemonstrationPhysics, TheFirstSecondsOfExpertOneReachTheStoredState) {
  const std::string module = GetParam();
  const std::string dir = test::source_path("content/demonstrations/" + module);
  const nlohmann::json check = nlohmann::json::parse(test::read_text(dir + "/physics_check.json"));
  const std::string trajectory = test::read_text(dir + "/" + check["trajectory"].get<std::string>());
  ASSERT_EQ(check["trajectory_fnv1a64"].get<std::string>(), fnv1a64_hex(trajectory))
      << module << ": the check is of another " << check["trajectory"]
      << " (run scripts/demonstrations)";
  const double until_s = check["until_s"].get<double>();

  test::TempDir tmp;
  const std::string part = tmp.file("first_seconds.csv");
  std::ofstream(part, std::ios::binary) << first_seconds(trajectory, until_s);
  SessionOptions o;
  o.scenario = test::source_path("scenarios/modules/" + module + ".json");
  o.input = "replay:" + part;
  o.db = tmp.file("record.sqlite");
  o.checkpoint_every_s = 0.0;
  o.quiet = true;
  std::ostringstream notes;
  const SessionResult r = run_attempt_session(o, nullptr, notes);
  ASSERT_EQ(r.end, SessionEnd::kCompleted) << r.error << notes.str();
  ASSERT_TRUE(r.world);
  EXPECT_NEAR(r.world->time_s(), until_s, 2e-3);
  EXPECT_EQ(hash_hex(r.run.state_hash), check["state_hash"].get<std::string>())
      << module << ": the module reaches another state after " << until_s
      << " s of expert_1 than when its demonstrations were replayed, so results.json and the "
         "rubric's benchmarks describe other physics: run scripts/demonstrations to replay "
         "and calibrate again";
}

INSTANTIATE_TEST_SUITE_P(C4C5Modules, DemonstrationPhysics,
                         ::testing::Values("02_c4c5_healthy", "03_c4c5_degenerated",
                                           "04_full_discectomy"));

}  // namespace
}  // namespace acdr
