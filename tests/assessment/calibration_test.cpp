// Benchmarks from an expert cohort: mean and sample SD, trimming, floors, task and pass rules,
// leave-one-out.
#include "assessment/calibration.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace acdr {
namespace {

Rubric rubric() {
  Rubric r;
  RubricTerm removed{"removed", 0.1, 1.0, true, 2.0};
  RubricTerm dwell{"dwell", 9.0, 9.0, false, 3.0, true};
  dwell.sd_floor = 0.5;
  r.terms = {removed, dwell};
  r.gates.push_back({"overloads", 0.0});
  r.task = TaskRule{"removed", 0.0};
  r.pass_score = 70.0;
  return r;
}

Metrics expert(double removed, double dwell) {
  Metrics m;
  m.set("removed", removed);
  m.set("dwell", dwell);
  m.set("overloads", 0);
  return m;
}

TEST(Calibration, MeanAndSampleSdPerTerm) {
  const std::vector<Metrics> cohort = {expert(0.8, 0), expert(0.9, 0), expert(0.85, 0),
                                       expert(0.95, 0)};
  std::string error;
  const auto c = calibrate(rubric(), cohort, {}, &error);
  ASSERT_TRUE(c) << error;
  ASSERT_EQ(c->terms.size(), 2u);
  EXPECT_NEAR(c->terms[0].mean, 0.875, 1e-12);
  // Sample SD (n - 1) of 0.8, 0.85, 0.9, 0.95.
  EXPECT_NEAR(c->terms[0].sd, std::sqrt(0.0125 / 3.0), 1e-12);
  EXPECT_FALSE(c->terms[0].floored);
  EXPECT_EQ(c->terms[0].experts, 4u);
  EXPECT_DOUBLE_EQ(c->terms[0].min, 0.8);
  EXPECT_DOUBLE_EQ(c->terms[0].max, 0.95);
  // No expert goes near a zone: SD 0, so the term's floor is what one SD is worth.
  EXPECT_DOUBLE_EQ(c->terms[1].mean, 0.0);
  EXPECT_DOUBLE_EQ(c->terms[1].measured_sd, 0.0);
  EXPECT_DOUBLE_EQ(c->terms[1].sd, 0.5);
  EXPECT_TRUE(c->terms[1].floored);
  // Task: a quarter of the experts' mean removal; pass: one SD below the mean.
  ASSERT_TRUE(c->task_min);
  EXPECT_NEAR(*c->task_min, 0.25 * 0.875, 1e-12);
  EXPECT_DOUBLE_EQ(c->pass_score, 40.0);

  const Rubric r = apply_calibration(rubric(), *c);
  EXPECT_NEAR(r.terms[0].expert_mean, 0.875, 1e-12);
  EXPECT_DOUBLE_EQ(r.terms[1].expert_sd, 0.5);
  EXPECT_DOUBLE_EQ(r.terms[0].weight, 2.0);  // kept
  EXPECT_TRUE(r.terms[1].safety);             // kept
  EXPECT_DOUBLE_EQ(r.terms[1].sd_floor, 0.5); // kept
  EXPECT_EQ(r.gates.size(), 1u);
  EXPECT_NEAR(r.task->min, 0.21875, 1e-12);
  EXPECT_DOUBLE_EQ(r.pass_score, 40.0);
}

TEST(Calibration, TrimmedMeanDropsTheEnds) {
  // Ten experts, one far off at each end: a 10 % trim drops both.
  std::vector<Metrics> cohort;
  for (double v : {0.1, 0.80, 0.82, 0.84, 0.86, 0.88, 0.90, 0.92, 0.94, 2.0})
    cohort.push_back(expert(v, 0));
  CalibrationMethod trimmed;
  trimmed.trim_fraction = 0.1;
  std::string error;
  const auto c = calibrate(rubric(), cohort, trimmed, &error);
  ASSERT_TRUE(c) << error;
  EXPECT_EQ(c->terms[0].experts, 8u);
  EXPECT_NEAR(c->terms[0].mean, 0.87, 1e-12);
  EXPECT_DOUBLE_EQ(c->terms[0].min, 0.1);  // the range is of all experts
  EXPECT_DOUBLE_EQ(c->terms[0].max, 2.0);
  const auto plain = calibrate(rubric(), cohort, {}, &error);
  ASSERT_TRUE(plain);
  EXPECT_GT(plain->terms[0].sd, 3 * c->terms[0].sd);
}

TEST(Calibration, PassSdsAndTaskShareAreTheMethods) {
  CalibrationMethod m;
  m.pass_sds = 0.5;
  m.task_share = 0.5;
  std::string error;
  const auto c = calibrate(rubric(), {expert(0.6, 0), expert(1.0, 0)}, m, &error);
  ASSERT_TRUE(c) << error;
  EXPECT_DOUBLE_EQ(c->pass_score, 45.0);
  EXPECT_NEAR(*c->task_min, 0.4, 1e-12);
}

TEST(Calibration, RefusesWhatCannotGiveABenchmark) {
  std::string error;
  EXPECT_FALSE(calibrate(rubric(), {expert(0.8, 0)}, {}, &error));
  EXPECT_NE(error.find("at least 2"), std::string::npos) << error;

  Metrics missing;
  missing.set("removed", 0.9);
  EXPECT_FALSE(calibrate(rubric(), {expert(0.8, 0), missing}, {}, &error));
  EXPECT_NE(error.find("expert 2 of 2 has no value of 'dwell'"), std::string::npos) << error;

  Metrics nan = expert(0.8, 0);
  nan.set("removed", std::nan(""));
  EXPECT_FALSE(calibrate(rubric(), {expert(0.8, 0), nan}, {}, &error));
  EXPECT_NE(error.find("non-finite value of 'removed'"), std::string::npos) << error;

  // Identical experts and no floor: no SD to score with.
  EXPECT_FALSE(calibrate(rubric(), {expert(0.8, 0), expert(0.8, 0)}, {}, &error));
  EXPECT_NE(error.find("removed"), std::string::npos) << error;
  EXPECT_NE(error.find("sd_floor"), std::string::npos) << error;

  CalibrationMethod bad;
  bad.trim_fraction = 0.5;
  EXPECT_FALSE(calibrate(rubric(), {expert(0.8, 0), expert(0.9, 0)}, bad, &error));
}

TEST(Calibration, LeaveOneOutScoresEachExpertAgainstTheOthers) {
  // Four experts close together pass against each other; an outlier scores against the
  // four's tight spread and does not.
  const std::vector<Metrics> cohort = {expert(0.84, 0), expert(0.86, 0), expert(0.85, 0),
                                       expert(0.87, 0), expert(0.3, 0)};
  std::string error;
  const auto loo = leave_one_out(rubric(), cohort, {}, &error);
  ASSERT_TRUE(loo) << error;
  ASSERT_EQ(loo->size(), 5u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ((*loo)[i].expert, i);
    EXPECT_TRUE((*loo)[i].score.passed) << i << ": " << (*loo)[i].score.score;
  }
  EXPECT_FALSE((*loo)[4].score.passed);
  // Scored against the others only: expert 5 against 0.84-0.87 (mean 0.855).
  const auto others = calibrate(rubric(), {cohort[0], cohort[1], cohort[2], cohort[3]}, {}, &error);
  ASSERT_TRUE(others);
  EXPECT_NEAR((*loo)[4].score.terms[0].score, 0.0, 1e-12);
}

}  // namespace
}  // namespace acdr
