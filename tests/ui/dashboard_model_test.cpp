// Tests of ui/dashboard_model: the dashboard's data from a real record (progress states,
// learning-curve points, the drill-down's series and bands) and the CSV of each view.
#include "ui/dashboard_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "tests/db/db_test_support.hpp"
#include "tests/ui/test_record.hpp"

namespace acdr {
namespace {

class DashboardModelTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir();
    path_ = dir_->file("record.sqlite");
    test::make_test_record(path_);
  }
  static void TearDownTestSuite() { delete dir_; }
  static Database open() { return test::open_or_fail(path_); }
  static test::TempDir* dir_;
  static std::string path_;
};
test::TempDir* DashboardModelTest::dir_ = nullptr;
std::string DashboardModelTest::path_;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST_F(DashboardModelTest, ReadsTraineesProgressAndAttempts) {
  Database db = open();
  auto model = load_dashboard(db);
  ASSERT_TRUE(model) << model.error().message;
  ASSERT_EQ(model->trainees.size(), 2u);
  const DashboardTrainee* ann = model->find_trainee("t-ann");
  const DashboardTrainee* ben = model->find_trainee("t-ben");
  ASSERT_TRUE(ann && ben);
  EXPECT_EQ(ann->attempts.size(), 4u);
  ASSERT_EQ(ann->progress.size(), 1u);
  EXPECT_EQ(progress_state(ann->progress[0]), "mastered");
  EXPECT_EQ(progress_state(ben->progress[0]), "passed");  // passed once, not twice in a row
  // The module's scenario was found, with its rubric (benchmarks for the drill-down).
  const ScenarioModel* scenario = model->scenario("no-nucleus-box");
  ASSERT_NE(scenario, nullptr);
  EXPECT_FALSE(scenario->rubric.terms.empty());
  // Learning curve: four points for t-ann, the second not passed.
  const auto curve = curve_attempts(*ann, "no-nucleus-box");
  ASSERT_EQ(curve.size(), 4u);
  EXPECT_TRUE(*curve[0]->passed);
  EXPECT_FALSE(*curve[1]->passed);
  EXPECT_LT(*curve[1]->score, *curve[0]->score);
}

TEST_F(DashboardModelTest, DefaultSelectionOpensTheLatestCompletedAttempt) {
  Database db = open();
  auto model = load_dashboard(db);
  ASSERT_TRUE(model);
  const DashboardSelection s = default_selection(*model);
  EXPECT_EQ(s.trainee_id, "t-ann");
  EXPECT_EQ(s.module_id, "no-nucleus-box");
  EXPECT_EQ(s.attempt_id, model->find_trainee("t-ann")->attempts.back().id);
}

TEST_F(DashboardModelTest, DrillDownHasSeriesAndOverloadBands) {
  Database db = open();
  auto model = load_dashboard(db);
  ASSERT_TRUE(model);
  const std::int64_t rough = model->find_trainee("t-ann")->attempts[1].id;
  std::string error;
  auto d = load_drill_down(db, rough, &error);
  ASSERT_TRUE(d) << error;
  ASSERT_TRUE(d->recording) << d->recording_error;
  const std::size_t n = d->recording->frames.size();
  EXPECT_EQ(d->t_s.size(), n);
  EXPECT_EQ(d->hand_force_N.size(), n);
  EXPECT_EQ(d->moment_Nm.size(), n);
  EXPECT_NEAR(d->duration_s, 3.0, 0.05);
  // The rough scoop overloaded the shaft: the bands cover the frames above the warning.
  ASSERT_FALSE(d->overload_warning.empty());
  const double warn = d->recording->summary.warning_moment_Nm;
  for (const TimeBand& b : d->overload_warning) {
    EXPECT_LE(b.t0_s, b.t1_s);
    const std::size_t i = d->frame_at(b.t0_s);
    EXPECT_GT(d->recording->frames[i].bending_moment_Nm, warn);
  }
  EXPECT_LE(*std::max_element(d->hand_force_N.begin(), d->hand_force_N.end()), 3.3f + 1e-6f);
  // Events came with it, the overload warnings among them.
  EXPECT_TRUE(std::any_of(d->record.events.begin(), d->record.events.end(),
                          [](const EventRecord& e) { return e.kind == "overload_warning"; }));
  EXPECT_EQ(d->frame_at(-1.0), 0u);
  EXPECT_EQ(d->frame_at(1e9), n - 1);
}

TEST_F(DashboardModelTest, UnknownAttemptIsAnError) {
  Database db = open();
  std::string error;
  EXPECT_FALSE(load_drill_down(db, 9999, &error));
  EXPECT_NE(error.find("9999"), std::string::npos) << error;
}

TEST_F(DashboardModelTest, CsvOfEachView) {
  Database db = open();
  auto model = load_dashboard(db);
  ASSERT_TRUE(model);
  // The progress matrix: one row per trainee and module.
  DashboardSelection none;
  auto lines = lines_of(dashboard_csv(*model, none, nullptr));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].rfind("trainee_id,module_id,state,", 0), 0u);
  EXPECT_NE(lines[1].find("t-ann,no-nucleus-box,mastered,4,3,2,2"), std::string::npos)
      << lines[1];
  EXPECT_EQ(dashboard_csv_name(none, nullptr), "dashboard-progress.csv");
  // A trainee's attempts with every metric as a column.
  DashboardSelection ben;
  ben.trainee_id = "t-ben";
  lines = lines_of(dashboard_csv(*model, ben, nullptr));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_NE(lines[0].find("peak_instrument_force_N"), std::string::npos);
  EXPECT_NE(lines[2].find(",completed,"), std::string::npos);
  EXPECT_EQ(dashboard_csv_name(ben, nullptr), "dashboard-t-ben.csv");
  // An attempt's frames.
  std::string error;
  auto d = load_drill_down(db, model->find_trainee("t-ben")->attempts[0].id, &error);
  ASSERT_TRUE(d) << error;
  lines = lines_of(dashboard_csv(*model, ben, d.get()));
  EXPECT_EQ(lines.size(), d->recording->frames.size() + 1);
  EXPECT_EQ(lines[0].rfind("t_s,hand_force_N,", 0), 0u);
  EXPECT_EQ(dashboard_csv_name(ben, d.get()),
            "dashboard-attempt-" + std::to_string(d->record.id) + ".csv");
}

}  // namespace
}  // namespace acdr
