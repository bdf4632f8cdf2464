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
  EXPECT_NE(s.reasons[0].find("spinal_cord_pll"), std::string::npos) << s.reasons[0];
  EXPECT_EQ(s.reasons[0].find("vertebral_artery_left"), std::string::npos) << s.reasons[0];
}

}  // namespace
}  // namespace acdr
