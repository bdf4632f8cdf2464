// The bundled modules' rubrics judge as docs/assessment.md says: on module 02 a run that enters
// the spinal cord zone scores clearly below a clean run of the same removal (metrics measured
// with content/demonstrations/02_c4c5_healthy/partial_clean_four and partial_zone_overshoot), and an attempt that
// removes nothing earns no safety points.
#include <string>

#include <gtest/gtest.h>

#include "assessment/scoring.hpp"
#include "scenarios/scenario_loader.hpp"
#include "tests/scenarios/scenario_test_support.hpp"

namespace acdr {
namespace {

Rubric rubric_of(const char* module) {
  const LoadResult loaded =
      load_scenario_file(test::source_path(std::string("scenarios/modules/") + module + ".json"));
  EXPECT_TRUE(loaded.ok()) << to_string(loaded.errors);
  return loaded.ok() ? loaded.model->rubric : Rubric{};
}

// What `acdr run` measured for the expert's first four scoops on module 02 (never near a zone),
// with the removal of a whole expert attempt (module 02's expert_5, results.json) so that the
// task counts as done: the four scoops' own 45.5 % is under the task line since the experts
// bite 81-83 % of the nucleus out with the rongeurs (docs/anatomy.md, "The tray's experts").
Metrics clean_four_scoops() {
  Metrics m;
  m.set("nucleus_removed_fraction", 0.8117283950617284);
  m.set("protected_removed_mm3", 0.0);
  m.set("peak_bending_moment_Nm", 0.02681584692516365);
  m.set("overload_events", 0);
  m.set("numerical_events", 0);
  m.set("zone_dwell_s", 0.0);
  m.set("zone_impulse_Ns", 0.0);
  m.set("zone_entries", 0);
  m.set("zone_over_limit_events", 0);
  m.set("never_events", 0);
  m.set("duration_s", 32.7);
  for (const char* zone : {"vertebral_artery_left", "vertebral_artery_right", "nerve_root_left",
                           "nerve_root_right", "spinal_cord_pll"})
    m.set(std::string("zone.") + zone + ".warnings", 0);
  // Measured before the bone was modelled: the experts' mean, the same for both runs below, so
  // it does not move their difference.
  m.set("endplate_peak_stress_MPa", 0.3754);
  return m;
}

TEST(BundledModules, EnteringTheCordZoneScoresClearlyBelowACleanRunOfTheSameRemoval) {
  const Rubric rubric = rubric_of("02_c4c5_healthy");
  const Metrics clean = clean_four_scoops();
  // The same four scoops with the fourth plunged 4.2 mm too deep into the cord zone: the same
  // removal, 2.29 s near the zone (1.95 s inside) at up to 0.65 N.
  Metrics zone = clean;
  zone.set("zone_dwell_s", 2.287999999999859);
  zone.set("zone_impulse_Ns", 0.2963493845630434);
  zone.set("zone_entries", 1);
  zone.set("zone_over_limit_events", 3);
  zone.set("never_events", 1);
  zone.set("zone.spinal_cord_pll.never_event", 1);
  zone.set("zone.spinal_cord_pll.warnings", 1);
  zone.set("duration_s", 35.6);
  const ScoreResult a = score_attempt(clean, rubric);
  const ScoreResult b = score_attempt(zone, rubric);
  EXPECT_TRUE(a.task_done);
  EXPECT_TRUE(b.task_done);
  // 15.2 points with the zone and material terms weighing 5 of 7; 13.3 since the time term
  // (weight 1, both far quicker than a whole attempt) joined them; 11.8 since the endplate
  // stress term (weight 1, the same for both) did.
  EXPECT_GE(a.score - b.score, 11.5) << "clean " << a.score << ", zone " << b.score;
  EXPECT_FALSE(b.passed);
  // The gates say it too, whatever the composite.
  int failed_gates = 0;
  for (const GateResult& g : b.gates) failed_gates += !g.passed;
  EXPECT_EQ(failed_gates, 3);  // zone_entries, zone_over_limit_events, the cord zone's warnings
  for (const GateResult& g : a.gates) EXPECT_TRUE(g.passed) << g.metric;
}

TEST(BundledModules, DoingNothingScoresNothingOnSafety) {
  for (const char* module : {"01_box_warmup", "02_c4c5_healthy", "03_c4c5_degenerated",
                             "04_full_discectomy"}) {
    const Rubric rubric = rubric_of(module);
    Metrics idle;  // the curette held still over the field: only its own weight on the shaft
    idle.set("nucleus_removed_fraction", 0.0);
    idle.set("protected_removed_mm3", 0.0);
    idle.set("peak_bending_moment_Nm", 0.012);
    idle.set("peak_instrument_force_N", 0.0);
    idle.set("overload_events", 0);
    idle.set("zone_dwell_s", 0.0);
    idle.set("zone_impulse_Ns", 0.0);
    idle.set("zone_entries", 0);
    idle.set("zone_over_limit_events", 0);
    idle.set("never_events", 0);
    idle.set("duration_s", 5.0);  // quick, but not efficient: it did nothing
    const ScoreResult s = score_attempt(idle, rubric);
    EXPECT_FALSE(s.task_done) << module;
    EXPECT_FALSE(s.passed) << module;
    // Only the removal term is left, far below the experts (the box's 0 is 3 SDs short: 20).
    EXPECT_LT(s.score, 10.5) << module;
    for (const TermScore& t : s.terms)
      if (t.safety || t.metric == "duration_s") {
        EXPECT_EQ(t.score, 0.0) << module << ": " << t.metric;
      }
  }
}

}  // namespace
}  // namespace acdr
