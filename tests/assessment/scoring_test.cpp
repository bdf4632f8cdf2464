// Composite score (50 + 10 z) and safety gates.
#include "assessment/scoring.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

Rubric rubric() {
  Rubric r;
  r.terms.push_back({"removed", 0.5, 0.1, true, 2.0});
  r.terms.push_back({"force", 1.0, 0.5, false, 1.0});
  r.gates.push_back({"overloads", 0.0});
  r.pass_score = 50.0;
  return r;
}

TEST(Scoring, ZScoresWeightedAndClipped) {
  Metrics m;
  m.set("removed", 0.6);   // z = +1 -> 60
  m.set("force", 2.0);     // z = -2 (lower is better) -> 30
  m.set("overloads", 0);
  const ScoreResult s = score_attempt(m, rubric());
  EXPECT_NEAR(s.terms[0].score, 60.0, 1e-12);
  EXPECT_NEAR(s.terms[1].score, 30.0, 1e-12);
  EXPECT_NEAR(s.score, (2 * 60.0 + 30.0) / 3.0, 1e-12);
  EXPECT_TRUE(s.passed);
  m.set("removed", 5.0);  // z = 45 -> clipped at 100
  EXPECT_NEAR(score_attempt(m, rubric()).terms[0].score, 100.0, 1e-12);
}

TEST(Scoring, GateFailsEvenWithHighScore) {
  Metrics m;
  m.set("removed", 0.9);
  m.set("force", 0.1);
  m.set("overloads", 1);
  const ScoreResult s = score_attempt(m, rubric());
  EXPECT_GT(s.score, 50.0);
  EXPECT_FALSE(s.passed);
  ASSERT_FALSE(s.reasons.empty());
  EXPECT_NE(s.reasons[0].find("overloads"), std::string::npos);
}

TEST(Scoring, MissingMetricAndNumericalTroubleFail) {
  Metrics m;
  m.set("removed", 0.9);
  m.set("overloads", 0);
  m.set("numerical_events", 1);
  const ScoreResult s = score_attempt(m, rubric());
  EXPECT_FALSE(s.passed);
  EXPECT_EQ(s.reasons.size(), 2u);  // missing 'force', numerical trouble
}

TEST(Scoring, NeverEventFailsWhateverTheRubricAndNamesTheZone) {
  Metrics m;
  m.set("removed", 0.9);
  m.set("force", 0.1);
  m.set("overloads", 0);
  m.set("never_events", 0);
  m.set("zone.vertebral_artery_left.never_event", 0);
  m.set("zone.spinal_cord_pll.never_event", 0);
  EXPECT_TRUE(score_attempt(m, rubric()).passed);
  m.set("never_events", 1);
  m.set("zone.spinal_cord_pll.never_event", 1);
  const ScoreResult s = score_attempt(m, rubric());  // the rubric has no gate on it
  EXPECT_GT(s.score, 50.0);
  EXPECT_FALSE(s.passed);
  ASSERT_EQ(s.reasons.size(), 1u);
  EXPECT_NE(s.reasons[0].find("the spinal cord / PLL zone"), std::string::npos) << s.reasons[0];
  EXPECT_EQ(s.reasons[0].find("vertebral_artery_left"), std::string::npos) << s.reasons[0];
}

TEST(Scoring, ABelowPassReasonNamesTheTermsFarFromTheExperts) {
  Rubric r = rubric();
  r.terms.push_back({"duration_s", 80.0, 4.0, false, 1.0});
  Metrics m;
  m.set("removed", 0.45);      // z = -0.5: not named
  m.set("force", 2.5);         // z = -3
  m.set("duration_s", 100.0);  // z = -5: the worst, named first
  m.set("overloads", 0);
  const ScoreResult s = score_attempt(m, r);
  EXPECT_FALSE(s.passed);
  ASSERT_EQ(s.reasons.size(), 1u);
  const std::string& why = s.reasons[0];
  EXPECT_EQ(why.find("composite score"), 0u) << why;
  const auto duration = why.find("Duration (s) 100 against the experts' 80 ± 4 (5.0 SD above)");
  const auto force = why.find("Force 2.5 against the experts' 1 ± 0.5 (3.0 SD above)");
  EXPECT_NE(duration, std::string::npos) << why;
  EXPECT_NE(force, std::string::npos) << why;
  EXPECT_LT(duration, force) << why;
  EXPECT_EQ(why.find("removed ="), std::string::npos) << why;
}

}  // namespace
}  // namespace acdr

namespace acdr {
namespace {

// A rubric as the anatomical modules write it: removal scored for quality, the shaft moment
// and the time near danger zones scored for safety, earned only by doing the task.
Rubric safety_rubric() {
  Rubric r;
  r.terms.push_back({"nucleus_removed_fraction", 0.6, 0.1, true, 2.0});
  r.terms.push_back({"peak_bending_moment_Nm", 0.08, 0.04, false, 1.0, true});
  r.terms.push_back({"zone_dwell_s", 0.0, 0.5, false, 1.0, true});
  r.gates.push_back({"overload_events", 0.0});
  r.task = TaskRule{"nucleus_removed_fraction", 0.15};
  return r;
}

TEST(Scoring, DoingNothingEarnsNoSafetyPoints) {
  Metrics idle;
  idle.set("nucleus_removed_fraction", 0.0);
  idle.set("peak_bending_moment_Nm", 0.0);  // never touched anything: 70 if it counted
  idle.set("zone_dwell_s", 0.0);
  idle.set("overload_events", 0);
  const ScoreResult s = score_attempt(idle, safety_rubric());
  EXPECT_FALSE(s.task_done);
  ASSERT_EQ(s.terms.size(), 3u);
  EXPECT_EQ(s.terms[1].score, 0.0);
  EXPECT_TRUE(s.terms[1].withheld);
  EXPECT_EQ(s.terms[2].score, 0.0);
  EXPECT_FALSE(s.terms[0].withheld);  // the task's own term is scored as it is
  EXPECT_EQ(s.score, 0.0);
  EXPECT_FALSE(s.passed);
  ASSERT_FALSE(s.reasons.empty());
  EXPECT_NE(s.reasons[0].find("the task was not done (nucleus_removed_fraction = 0, at least 0.15"),
            std::string::npos)
      << s.reasons[0];

  // The same hands, having done the task: the safety terms count.
  Metrics worked = idle;
  worked.set("nucleus_removed_fraction", 0.6);
  const ScoreResult w = score_attempt(worked, safety_rubric());
  EXPECT_TRUE(w.task_done);
  EXPECT_NEAR(w.terms[1].score, 70.0, 1e-12);
  EXPECT_NEAR(w.terms[2].score, 50.0, 1e-12);
  EXPECT_NEAR(w.score, (2 * 50.0 + 70.0 + 50.0) / 4.0, 1e-12);
  EXPECT_TRUE(w.passed);
}

TEST(Scoring, TimeInADangerZoneCostsPoints) {
  Metrics clean;
  clean.set("nucleus_removed_fraction", 0.3);
  clean.set("peak_bending_moment_Nm", 0.06);
  clean.set("zone_dwell_s", 0.0);
  clean.set("overload_events", 0);
  Metrics zone = clean;
  zone.set("zone_dwell_s", 1.7);
  const double a = score_attempt(clean, safety_rubric()).score;
  const double b = score_attempt(zone, safety_rubric()).score;
  EXPECT_NEAR(a - b, 34.0 / 4.0, 1e-9);  // 50 -> 16 on a term of weight 1 out of 4
}

TEST(Scoring, AGateOnOneZoneMetric) {
  Rubric r = rubric();
  r.gates.push_back({"zone.spinal_cord_pll.inside_s", 0.0});
  Metrics m;
  m.set("removed", 0.9);
  m.set("force", 0.1);
  m.set("overloads", 0);
  m.set("zone.spinal_cord_pll.inside_s", 1.7);
  const ScoreResult s = score_attempt(m, r);
  EXPECT_FALSE(s.passed);
  ASSERT_EQ(s.gates.size(), 2u);
  EXPECT_FALSE(s.gates[1].passed);
  ASSERT_EQ(s.reasons.size(), 1u);
  EXPECT_NE(s.reasons[0].find("zone.spinal_cord_pll.inside_s = 1.7 is above its limit 0"),
            std::string::npos)
      << s.reasons[0];
}

}  // namespace
}  // namespace acdr

namespace acdr {
namespace {

TEST(Scoring, TimeIsEarnedOnlyByDoingTheTask) {
  Rubric r;
  r.terms.push_back({"nucleus_removed_fraction", 0.6, 0.1, true, 2.0});
  r.terms.push_back({"duration_s", 80.0, 3.0, false, 1.0});
  r.gates.push_back({"overload_events", 0.0});
  r.task = TaskRule{"nucleus_removed_fraction", 0.15};
  Metrics quick;  // 5 s and nothing removed: not efficient, absent
  quick.set("nucleus_removed_fraction", 0.0);
  quick.set("duration_s", 5.0);
  quick.set("overload_events", 0);
  ScoreResult s = score_attempt(quick, r);
  EXPECT_TRUE(s.terms[1].withheld);
  EXPECT_EQ(s.terms[1].score, 0.0);
  EXPECT_EQ(s.score, 0.0);
  quick.set("nucleus_removed_fraction", 0.6);  // the same time with the task done
  s = score_attempt(quick, r);
  EXPECT_FALSE(s.terms[1].withheld);
  EXPECT_EQ(s.terms[1].score, 100.0);
}

// An attempt that hesitates until the time limit ends it, with too little removed: its time
// scores nothing for want of the task, and the reason still says it was slow.
TEST(Scoring, ASlowAttemptWithoutTheTaskIsToldItWasSlow) {
  Rubric r;
  r.terms.push_back({"nucleus_removed_fraction", 0.6, 0.1, true, 2.0});
  r.terms.push_back({"duration_s", 80.0, 3.0, false, 1.0});
  r.task = TaskRule{"nucleus_removed_fraction", 0.45};
  Metrics slow;
  slow.set("nucleus_removed_fraction", 0.35);
  slow.set("duration_s", 90.0);
  const ScoreResult s = score_attempt(slow, r);
  EXPECT_FALSE(s.task_done);
  EXPECT_TRUE(s.terms[1].withheld);
  ASSERT_EQ(s.reasons.size(), 2u);
  EXPECT_NE(s.reasons[1].find("Duration (s) 90 against the experts' 80 ± 3 (3.3 SD above)"),
            std::string::npos)
      << s.reasons[1];
  EXPECT_NE(s.reasons[1].find("(2.5 SD below)"), std::string::npos) << s.reasons[1];
}

}  // namespace
}  // namespace acdr
