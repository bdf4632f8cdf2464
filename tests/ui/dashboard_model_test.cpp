// Tests of ui/dashboard_model: the dashboard's data from a real record (progress states,
// learning-curve points, the drill-down's series, bands, benchmarks and replay geometry) and
// the CSV of each view.
#include "ui/dashboard_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/rigid/instrument.hpp"
#include "scenarios/scenario_loader.hpp"
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

// The drill-down reads its module's scenario once: the rubric for the benchmarks, and the
// replay's walls and instrument, placed as the engine places them.
TEST_F(DashboardModelTest, DrillDownHasTheBenchmarksAndTheReplayGeometry) {
  Database db = open();
  auto model = load_dashboard(db);
  ASSERT_TRUE(model);
  std::string error;
  auto d = load_drill_down(db, model->find_trainee("t-ann")->attempts[0].id, &error);
  ASSERT_TRUE(d) << error;
  EXPECT_EQ(d->scenario_error, "");
  LoadResult scenario = load_scenario_file(test::kSceneData + "empty_box.json");
  ASSERT_TRUE(scenario.ok());
  ASSERT_TRUE(d->rubric);
  ASSERT_EQ(d->rubric->terms.size(), scenario.model->rubric.terms.size());
  EXPECT_EQ(d->rubric->terms[0].metric, scenario.model->rubric.terms[0].metric);
  // The open box: a floor and four walls; its bounds hold every tip position.
  EXPECT_EQ(d->replay.walls.size(), 5u);
  for (const Collider& c : d->replay.walls) EXPECT_EQ(c.kind, ColliderKind::kBox);
  for (const Frame& f : d->recording->frames)
    EXPECT_TRUE(d->replay.bounds.contains(f.tip_m)) << f.t_s;
  // The instrument at a recorded grip pose is where the engine puts it.
  const Pose grip = d->recording->frames[d->frame_at(1.5)].instrument;
  std::vector<Collider> placed, engine;
  d->replay.instrument_at(grip, 1.5, placed);
  InstrumentGeometry(scenario.model->world.instrument)
      .world_colliders(grip, Vec3::Zero(), Vec3::Zero(), engine);
  ASSERT_EQ(placed.size(), engine.size());
  ASSERT_FALSE(placed.empty());
  for (std::size_t i = 0; i < placed.size(); ++i) {
    EXPECT_EQ(placed[i].pose.position, engine[i].pose.position);
    EXPECT_EQ(placed[i].pose.orientation.coeffs(), engine[i].pose.orientation.coeffs());
  }
}

// A scenario file gone since the attempt: the drill-down says so and shows the rest.
TEST_F(DashboardModelTest, DrillDownWithoutItsScenarioFileStillHasItsSeries) {
  test::TempDir dir;
  const std::string scenario = dir.file("gone.json");
  std::filesystem::copy_file(test::kSceneData + "empty_box.json", scenario);
  const std::string path = dir.file("record.sqlite");
  SessionOptions o;
  o.scenario = scenario;
  o.input = "replay:" + test::kSceneData + "short_scoop.csv";
  o.db = path;
  std::ostringstream notes;
  const SessionResult run = run_attempt_session(o, nullptr, notes);
  ASSERT_TRUE(run.ran()) << run.error;
  std::filesystem::remove(scenario);
  Database db = test::open_or_fail(path);
  std::string error;
  auto d = load_drill_down(db, run.attempt_id, &error);
  ASSERT_TRUE(d) << error;
  EXPECT_NE(d->scenario_error.find("gone.json"), std::string::npos) << d->scenario_error;
  EXPECT_FALSE(d->rubric);
  EXPECT_TRUE(d->replay.walls.empty());
  EXPECT_TRUE(d->replay.tray.empty());
  ASSERT_TRUE(d->recording);
  EXPECT_EQ(d->t_s.size(), d->recording->frames.size());
  EXPECT_TRUE(d->replay.bounds.contains(d->recording->frames.back().tip_m));
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
  EXPECT_NE(lines[0].find(",duration_s,realtime_factor,score,"), std::string::npos) << lines[0];
  EXPECT_NE(lines[2].find(",completed,"), std::string::npos);
  EXPECT_EQ(dashboard_csv_name(ben, nullptr), "dashboard-t-ben.csv");
  // An attempt's frames.
  std::string error;
  auto d = load_drill_down(db, model->find_trainee("t-ben")->attempts[0].id, &error);
  ASSERT_TRUE(d) << error;
  ASSERT_TRUE(d->record.realtime_factor.has_value());  // the replay's own, measured
  EXPECT_GT(*d->record.realtime_factor, 0.0);
  lines = lines_of(dashboard_csv(*model, ben, d.get()));
  EXPECT_EQ(lines.size(), d->recording->frames.size() + 1);
  EXPECT_EQ(lines[0].rfind("t_s,hand_force_N,", 0), 0u);
  EXPECT_EQ(dashboard_csv_name(ben, d.get()),
            "dashboard-attempt-" + std::to_string(d->record.id) + ".csv");
}

// A scene with a tray: the replay draws the instrument the hand held at each moment, as the
// recording's exchanges say (the blade, then the rongeur the hand took at 0.5 s).
TEST(DashboardModelTray, TheReplayDrawsTheInstrumentInHand) {
  test::TempDir dir;
  std::ifstream in(test::kSceneData + "empty_box.json");
  nlohmann::json s = nlohmann::json::parse(in);
  nlohmann::json blade = s["world"]["instrument"];
  blade["name"] = "blade";
  const nlohmann::json rongeur = {{"name", "rongeur"}, {"shape", "rongeur"},
                                  {"jaw_length_mm", 6},  {"jaw_width_mm", 3},
                                  {"shaft_length_mm", 80}, {"shaft_diameter_mm", 2},
                                  {"yield_stress_MPa", 500}, {"mass_g", 30}};
  s["world"].erase("instrument");
  s["world"]["instruments"] = nlohmann::json::array({blade, rongeur});
  const std::string scenario = dir.file("tray.json");
  std::ofstream(scenario) << s.dump(2);
  // The grip held above the box for 1.5 s; the hand asks for the rongeur from 0.5 s.
  const std::string trajectory = dir.file("exchange.csv");
  {
    std::ofstream t(trajectory);
    t << "t_s,x_m,y_m,z_m,qw,qx,qy,qz,instrument\n";
    for (int i = 0; i <= 150; ++i)
      t << i * 0.01 << ",0,0,0.11,1,0,0,0," << (i < 50 ? 0 : 1) << "\n";
  }
  SessionOptions o;
  o.scenario = scenario;
  o.input = "replay:" + trajectory;
  o.db = dir.file("record.sqlite");
  std::ostringstream notes;
  const SessionResult run = run_attempt_session(o, nullptr, notes);
  ASSERT_TRUE(run.ran()) << run.error << notes.str();
  Database db = test::open_or_fail(o.db);
  std::string error;
  auto d = load_drill_down(db, run.attempt_id, &error);
  ASSERT_TRUE(d) << error;
  ASSERT_EQ(d->replay.tray.size(), 2u);
  ASSERT_EQ(d->replay.exchanges.size(), 1u);
  EXPECT_NEAR(d->replay.exchanges[0].t_s, 0.5, 0.02);
  EXPECT_EQ(instrument_in_hand(d->replay.exchanges, 0.2), 0);
  EXPECT_EQ(instrument_in_hand(d->replay.exchanges, 1.0), 1);
  LoadResult loaded = load_scenario_file(scenario);
  ASSERT_TRUE(loaded.ok());
  const Pose grip = d->recording->frames.back().instrument;
  for (const auto& [t, k] : {std::pair<double, int>{0.2, 0}, {1.0, 1}}) {
    std::vector<Collider> placed, engine;
    d->replay.instrument_at(grip, t, placed);
    InstrumentGeometry(loaded.model->world.instruments[static_cast<std::size_t>(k)])
        .world_colliders(grip, Vec3::Zero(), Vec3::Zero(), engine);
    ASSERT_EQ(placed.size(), engine.size()) << "at " << t << " s";
    for (std::size_t i = 0; i < placed.size(); ++i) {
      EXPECT_EQ(placed[i].kind, engine[i].kind);
      EXPECT_EQ(placed[i].pose.position, engine[i].pose.position);
    }
  }
}

// The progress matrix lists every module of the curriculum for every trainee, from the first
// attempt of anyone: the record learns the curriculum from its scenario files, not from attempts.
TEST(DashboardModelCurriculum, EveryModuleOfTheCurriculumForEveryTrainee) {
  test::TempDir dir;
  std::ifstream in(test::kSceneData + "empty_box.json");
  const nlohmann::json box = nlohmann::json::parse(in);
  std::vector<std::string> files;
  for (int order = 1; order <= 4; ++order) {
    nlohmann::json s = box;
    s["id"] = "course-" + std::to_string(order);
    s["curriculum"] = "course";
    s["module_order"] = order;
    files.push_back(dir.file("m" + std::to_string(order) + ".json"));
    std::ofstream(files.back()) << s.dump(2);
  }
  SessionOptions o;
  o.scenario = files[0];
  o.input = "replay:" + test::kSceneData + "short_scoop.csv";
  o.db = dir.file("record.sqlite");
  o.trainee = "t-ann";
  std::ostringstream notes;
  ASSERT_EQ(run_attempt_session(o, nullptr, notes).end, SessionEnd::kCompleted) << notes.str();
  o.scenario = files[2];
  o.trainee = "t-ben";
  EXPECT_EQ(run_attempt_session(o, nullptr, notes).end, SessionEnd::kLocked);
  o.scenario = files[0];
  ASSERT_EQ(run_attempt_session(o, nullptr, notes).end, SessionEnd::kCompleted) << notes.str();

  Database db = test::open_or_fail(o.db);
  auto model = load_dashboard(db);
  ASSERT_TRUE(model) << model.error().message;
  ASSERT_EQ(model->modules.size(), 4u);
  ASSERT_EQ(model->trainees.size(), 2u);
  for (const DashboardTrainee& t : model->trainees) {
    ASSERT_EQ(t.progress.size(), 4u) << t.info.id;
    EXPECT_EQ(t.progress[0].module_id, "course-1");
    EXPECT_EQ(progress_state(t.progress[3]), "locked") << t.info.id;
  }
}

}  // namespace
}  // namespace acdr
