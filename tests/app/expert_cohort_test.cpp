// Tests of app/expert_cohort: the cohort from a training record (by trainee, completed attempts
// only) and from replayed demonstrations (the same metrics as the stored attempts of the same
// trajectories), and the benchmark table.
#include "app/expert_cohort.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/attempt_session.hpp"
#include "scenarios/scenario_loader.hpp"
#include "tests/app/test_scenes.hpp"
#include "tests/db/db_test_support.hpp"

namespace acdr {
namespace {

std::int64_t attempt(const std::string& db, const std::string& trajectory,
                     const std::optional<std::string>& trainee) {
  SessionOptions o;
  o.scenario = test::kSceneData + "small_box.json";
  o.input = "replay:" + test::kSceneData + trajectory;
  o.db = db;
  o.trainee = trainee;
  std::ostringstream notes;
  const SessionResult r = run_attempt_session(o, nullptr, notes);
  EXPECT_TRUE(r.error.empty()) << r.error;
  return r.attempt_id;
}

TEST(ExpertCohort, FromARecordByTraineeAndFromTheSameTrajectoriesReplayed) {
  test::TempDir dir;
  const std::string db = dir.file("record.sqlite");
  attempt(db, "short_scoop.csv", std::string("expert-a"));
  attempt(db, "novice_scoop.csv", std::string("novice"));
  attempt(db, "novice_scoop.csv", std::string("expert-b"));
  attempt(db, "short_scoop.csv", std::nullopt);  // practice

  const LoadResult scene = load_scenario_file(test::kSceneData + "small_box.json");
  ASSERT_TRUE(scene.ok()) << to_string(scene.errors);
  std::string error;
  const auto experts = cohort_from_record(db, scene.model->id, {"expert-a", "expert-b"}, &error);
  ASSERT_TRUE(experts) << error;
  ASSERT_EQ(experts->size(), 2u);
  EXPECT_NE((*experts)[0].label.find("(expert-a)"), std::string::npos) << (*experts)[0].label;
  EXPECT_NE((*experts)[1].label.find("(expert-b)"), std::string::npos) << (*experts)[1].label;
  const auto everyone = cohort_from_record(db, scene.model->id, {}, &error);
  ASSERT_TRUE(everyone) << error;
  EXPECT_EQ(everyone->size(), 4u);  // practice included
  EXPECT_TRUE(cohort_from_record(db, "no-such-module", {}, &error)->empty());

  // Replaying the same two trajectories gives the stored metrics, bit for bit.
  const auto replayed = cohort_from_trajectories(
      *scene.model, {test::kSceneData + "short_scoop.csv", test::kSceneData + "novice_scoop.csv"},
      &error);
  ASSERT_TRUE(replayed) << error;
  ASSERT_EQ(replayed->size(), 2u);
  EXPECT_EQ((*replayed)[0].label, "short_scoop.csv");
  EXPECT_EQ((*replayed)[0].metrics.values, (*experts)[0].metrics.values);
  EXPECT_EQ((*replayed)[1].metrics.values, (*experts)[1].metrics.values);

  // The benchmark table lists each term and the rules.
  Rubric rubric = scene.model->rubric;
  std::vector<Metrics> m = {(*experts)[0].metrics, (*experts)[1].metrics};
  for (RubricTerm& t : rubric.terms) t.sd_floor = 1e-3;
  const auto c = calibrate(rubric, m, {}, &error);
  ASSERT_TRUE(c) << error;
  const std::string table = calibration_table(rubric, *c);
  for (const RubricTerm& t : rubric.terms) EXPECT_NE(table.find(t.metric), std::string::npos) << table;
  EXPECT_NE(table.find("pass score: 40 (2 experts)"), std::string::npos) << table;
}

TEST(ExpertCohort, ReadingTheRecordOrTheFolderFailsClearly) {
  test::TempDir dir;
  std::string error;
  EXPECT_FALSE(cohort_from_record(dir.file("missing.sqlite"), "m", {}, &error));
  EXPECT_FALSE(error.empty());
  EXPECT_FALSE(expert_demonstrations(dir.file("no-folder"), &error));
  EXPECT_NE(error.find("no-folder"), std::string::npos) << error;
  EXPECT_FALSE(expert_demonstrations(dir.path().string(), &error));
  EXPECT_NE(error.find("no expert_*.csv"), std::string::npos) << error;
  for (const char* name : {"expert_2.csv", "expert_1.csv", "expert_1.cup.csv",
                           "expert_1.waypoints.csv", "novice_drift.csv"})
    std::ofstream(dir.file(name)) << "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";
  const auto files = expert_demonstrations(dir.path().string(), &error);
  ASSERT_TRUE(files) << error;
  ASSERT_EQ(files->size(), 2u);
  EXPECT_EQ(std::filesystem::path((*files)[0]).filename(), "expert_1.csv");
  EXPECT_EQ(std::filesystem::path((*files)[1]).filename(), "expert_2.csv");
}

}  // namespace
}  // namespace acdr
