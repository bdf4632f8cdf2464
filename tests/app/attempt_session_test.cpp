// Tests of app/attempt_session: one attempt from its scenario file to the record, headless and
// live through a view (a test double here: the session needs no screen). Refusals come before
// anything is stored; the progression gate locks a module unless an instructor overrides; a
// live attempt is stored before its score shows; an abandoned one is stored as aborted; a view
// that cannot open leaves the attempt headless or aborted, as the case may be.
#include "app/attempt_session.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <vector>

#include "db/attempt_store.hpp"
#include "db/progression.hpp"
#include "db/outbox.hpp"
#include "engine/devices/trajectory.hpp"
#include "tests/app/test_scenes.hpp"
#include "tests/db/db_test_support.hpp"
#include "tests/support/test_lrs_process.hpp"

namespace acdr {
namespace {

using namespace std::chrono_literals;

// A 0.3 s trajectory from the test box's start pose, 3 mm down (live attempts run in real time).
std::string write_short_trajectory(const test::TempDir& dir) {
  const std::string path = dir.file("short.csv");
  std::ofstream out(path);
  out << "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";
  for (int i = 0; i <= 6; ++i)
    out << 0.05 * i << ",0,0," << 0.11 - 0.0005 * i << ",1,0,0,0\n";
  return path;
}

// The test box as module `id` at `order` in curriculum "t-course".
std::string write_module(const test::TempDir& dir, const std::string& id, int order) {
  std::ifstream in(test::kSceneData + "empty_box.json");
  nlohmann::json s = nlohmann::json::parse(in);
  s["id"] = id;
  s["curriculum"] = "t-course";
  s["module_order"] = order;
  const std::string path = dir.file(id + ".json");
  std::ofstream(path) << s.dump(2);
  return path;
}

SessionOptions replay_options(const test::TempDir& dir, const std::string& trajectory) {
  SessionOptions o;
  o.scenario = test::kSceneData + "empty_box.json";
  o.input = "replay:" + trajectory;
  o.db = dir.file("record.sqlite");
  return o;
}

AttemptRecord stored(const std::string& db_path, std::int64_t id) {
  Database db = test::open_or_fail(db_path);
  auto loaded = load_attempt(db, id);
  EXPECT_TRUE(loaded && loaded.value()) << "attempt " << id;
  return loaded && loaded.value() ? *loaded.value() : AttemptRecord{};
}

TEST(AttemptSession, AHeadlessReplayIsStoredWithItsRecording) {
  test::TempDir dir;
  SessionOptions o = replay_options(dir, test::kSceneData + "short_scoop.csv");
  o.trainee = "t1";
  o.record = dir.file("attempt.rec");
  std::ostringstream notes;
  const SessionResult r = run_attempt_session(o, nullptr, notes);
  ASSERT_TRUE(r.ran()) << r.error;
  EXPECT_EQ(r.end, SessionEnd::kCompleted);
  EXPECT_EQ(r.stored_as, "completed");
  EXPECT_EQ(r.run.end, AttemptEnd::kInputEnded);
  ASSERT_TRUE(r.world);
  EXPECT_NEAR(r.world->time_s(), 3.0, 0.01);
  EXPECT_FALSE(r.haptics);      // not a live attempt
  EXPECT_FALSE(r.checkpoints);  // checkpoints on the stepping thread: no writer thread
  EXPECT_EQ(r.db_path, o.db);
  const AttemptRecord a = stored(o.db, r.attempt_id);
  EXPECT_EQ(a.status, AttemptStatus::kCompleted);
  EXPECT_EQ(a.input_device, o.input);
  EXPECT_EQ(a.module_id, "no-nucleus-box");
  // The replay's own real-time factor, the figure `acdr run --json` prints.
  ASSERT_GT(r.run.wall_s, 0.0);
  ASSERT_TRUE(a.realtime_factor.has_value());
  EXPECT_DOUBLE_EQ(*a.realtime_factor, r.world->time_s() / r.run.wall_s);
  ASSERT_TRUE(a.recording);
  EXPECT_EQ(a.metrics.values, r.run.metrics.values);
  // The recording file is the stored recording.
  std::ifstream file(o.record, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(file)),
                                        std::istreambuf_iterator<char>());
  EXPECT_EQ(bytes, a.recording->bytes);
}

// A recording file that cannot be written (here: its folder does not exist) loses nothing:
// the attempt is stored completed with its recording, and the session says which file failed
// with the "record not written" end.
TEST(AttemptSession, ARecordingFileThatCannotBeWrittenStillStoresTheAttempt) {
  test::TempDir dir;
  SessionOptions o = replay_options(dir, test::kSceneData + "short_scoop.csv");
  o.trainee = "t1";
  o.record = dir.file("no-such-folder/attempt.rec");
  std::ostringstream notes;
  const SessionResult r = run_attempt_session(o, nullptr, notes);
  EXPECT_EQ(r.end, SessionEnd::kRecordNotWritten);
  EXPECT_NE(r.error.find(o.record), std::string::npos) << r.error;
  EXPECT_EQ(r.stored_as, "completed");
  const AttemptRecord a = stored(o.db, r.attempt_id);
  EXPECT_EQ(a.status, AttemptStatus::kCompleted);
  ASSERT_TRUE(a.recording);
  EXPECT_EQ(a.metrics.values, r.run.metrics.values);
}

TEST(AttemptSession, AStoredAttemptIsSentWhenTheLrsConfigurationSaysSo) {
  if (std::string missing = test_support::test_lrs_missing(ACDR_SOURCE_DIR); !missing.empty()) {
    GTEST_SKIP() << missing;
  }
  test::TempDir dir;
  test_support::TestLrsOptions lrs_options;
  lrs_options.source_dir = ACDR_SOURCE_DIR;
  lrs_options.store = dir.file("lrs.jsonl");
  std::string error;
  test_support::LrsProcess lrs = test_support::LrsProcess::start_test_lrs(lrs_options, &error);
  ASSERT_TRUE(lrs.running()) << error;
  const std::string config = dir.file("lrs.json");
  std::ofstream(config) << R"({"endpoint": ")" << lrs.endpoint() << R"(", "key": ")"
                        << lrs_options.key << R"(", "secret": ")" << lrs_options.secret
                        << R"(", "activity_iri_base": "https://training.example.org/acdr/",
                        "send_after_attempt": true})";
  chmod(config.c_str(), 0600);

  SessionOptions o = replay_options(dir, test::kSceneData + "short_scoop.csv");
  o.trainee = "t1";
  o.lrs_config = config;
  std::ostringstream notes;
  const SessionResult r = run_attempt_session(o, nullptr, notes);
  ASSERT_TRUE(r.ran()) << r.error;
  ASSERT_TRUE(r.delivery);
  EXPECT_TRUE(r.delivery->emptied()) << r.delivery->stopped;
  EXPECT_EQ(r.delivery->stored, 2);  // scored, and passed or failed
  EXPECT_EQ(test_support::stored_ids(lrs_options.store).size(), 2u);
  Database db = test::open_or_fail(o.db);
  for (const OutboxItem& item : list_outbox(db).value()) {
    EXPECT_EQ(item.state, OutboxState::kSent);
    EXPECT_NE(item.statement.find("https://training.example.org/acdr/modules/no-nucleus-box"),
              std::string::npos);
  }

  // A broken configuration is refused before anything is stored.
  std::ofstream(config) << R"({"endpoint": "ftp://lrs.example.org/"})";
  const SessionResult refused = run_attempt_session(o, nullptr, notes);
  EXPECT_EQ(refused.end, SessionEnd::kBadInput);
  EXPECT_NE(refused.error.find("http:// or https://"), std::string::npos) << refused.error;
  EXPECT_EQ(list_attempts(db).value().size(), 1u);
}

TEST(AttemptSession, BadFilesAndInputsAreRefusedBeforeTheRecordIsOpened) {
  test::TempDir dir;
  const std::string trajectory = test::kSceneData + "short_scoop.csv";
  struct Case {
    std::string scenario, input, expect;
  };
  const std::vector<Case> cases = {
      {dir.file("missing.json"), "replay:" + trajectory, "missing.json"},
      {test::kSceneData + "empty_box.json", "joystick", "unknown input 'joystick'"},
      {test::kSceneData + "empty_box.json", "udp:70000", "port number 1-65535"},
      {test::kSceneData + "empty_box.json", "replay:" + dir.file("none.csv"), "none.csv"},
      // Without a view the mouse has nothing to drive it.
      {test::kSceneData + "empty_box.json", "mouse", "--input mouse needs a window"},
  };
  for (const Case& c : cases) {
    SessionOptions o = replay_options(dir, trajectory);
    o.scenario = c.scenario;
    o.input = c.input;
    std::ostringstream notes;
    const SessionResult r = run_attempt_session(o, nullptr, notes);
    EXPECT_EQ(r.end, SessionEnd::kBadInput) << c.input;
    EXPECT_NE(r.error.find(c.expect), std::string::npos) << r.error;
    EXPECT_NE(r.error.back(), '\n');
    EXPECT_FALSE(std::filesystem::exists(o.db)) << c.input;
  }
}

TEST(AttemptSession, ALockedModuleIsRefusedUnlessAnInstructorOverrides) {
  test::TempDir dir;
  const std::string trajectory = write_short_trajectory(dir);
  std::ostringstream notes;
  // The first module registers the curriculum; the second then waits for its mastery.
  SessionOptions first = replay_options(dir, trajectory);
  first.scenario = write_module(dir, "t-first", 1);
  ASSERT_TRUE(run_attempt_session(first, nullptr, notes).ran());
  SessionOptions second = first;
  second.scenario = write_module(dir, "t-second", 2);
  second.trainee = "t1";
  SessionResult r = run_attempt_session(second, nullptr, notes);
  EXPECT_EQ(r.end, SessionEnd::kLocked);
  EXPECT_NE(r.error.find("t-first"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("with --override --override-by NAME"), std::string::npos) << r.error;
  // An override needs the name of who decided.
  second.override_lock = true;
  r = run_attempt_session(second, nullptr, notes);
  EXPECT_EQ(r.end, SessionEnd::kBadInput);
  EXPECT_EQ(r.error, "--override needs --override-by NAME (who decided)");
  second.override_by = "dr-who";
  second.override_reason = "demonstration";
  r = run_attempt_session(second, nullptr, notes);
  ASSERT_EQ(r.end, SessionEnd::kCompleted) << r.error;
  const AttemptRecord a = stored(second.db, r.attempt_id);
  EXPECT_TRUE(a.override_lock);
  EXPECT_EQ(a.override_by, "dr-who");
  EXPECT_EQ(a.trainee_id, std::optional<std::string>("t1"));
}

// The curriculum is known from its scenario files, not learned from attempts: on a new record
// the second module is locked from the very first attempt.
TEST(AttemptSession, ANewRecordKnowsTheWholeCurriculumSoTheLockHoldsAtOnce) {
  test::TempDir dir;
  const std::string trajectory = write_short_trajectory(dir);
  write_module(dir, "t-first", 1);
  write_module(dir, "t-third", 3);
  SessionOptions second = replay_options(dir, trajectory);
  second.scenario = write_module(dir, "t-second", 2);
  second.trainee = "t1";
  std::ostringstream notes;
  const SessionResult r = run_attempt_session(second, nullptr, notes);
  EXPECT_EQ(r.end, SessionEnd::kLocked) << r.error;
  EXPECT_NE(r.error.find("module 't-second' is locked for trainee 't1': pass 't-first'"),
            std::string::npos)
      << r.error;
  // Every module of the folder's curriculum is registered, so the progress lists all three.
  Database db = test::open_or_fail(second.db);
  auto progress = trainee_progress(db, "t1");
  ASSERT_TRUE(progress) << progress.error().message;
  ASSERT_EQ(progress->size(), 3u);
  EXPECT_EQ((*progress)[0].module_id, "t-first");
  EXPECT_TRUE((*progress)[0].unlocked);
  EXPECT_FALSE((*progress)[1].unlocked);
  EXPECT_FALSE((*progress)[2].unlocked);
  EXPECT_EQ((*progress)[2].missing_prerequisites, std::vector<std::string>{"t-second"});
  auto attempts = list_attempts(db);
  ASSERT_TRUE(attempts);
  EXPECT_TRUE(attempts->empty());  // refused before an attempt began
}

// The bundled set: module 02 refused on a new record for a trainee without module 01, with the
// curriculum given as a folder (--curriculum) as well as taken from the scenario's own.
TEST(AttemptSession, TheBundledModule02IsLockedOnANewRecord) {
  test::TempDir dir;
  const std::string modules = std::string(ACDR_SOURCE_DIR) + "/scenarios/modules";
  SessionOptions o;
  o.scenario = modules + "/02_c4c5_healthy.json";
  o.input = "replay:" + std::string(ACDR_SOURCE_DIR) + "/content/demonstrations/02_c4c5_healthy/novice_corner.csv";
  o.db = dir.file("new.sqlite");
  o.trainee = "bob";
  std::ostringstream notes;
  SessionResult r = run_attempt_session(o, nullptr, notes);
  EXPECT_EQ(r.end, SessionEnd::kLocked) << r.error;
  EXPECT_NE(r.error.find("pass 'box-warmup' on 2 attempts in a row first"), std::string::npos)
      << r.error;
  EXPECT_EQ(notes.str(), "");  // every file of the bundled folder is a valid scenario

  // A copy of the module alone in a folder, with the bundled folder given as the curriculum.
  const std::string alone = dir.file("02.json");
  std::filesystem::copy_file(o.scenario, alone);
  o.scenario = alone;
  o.curriculum_dir = modules;
  o.db = dir.file("new2.sqlite");
  r = run_attempt_session(o, nullptr, notes);
  EXPECT_EQ(r.end, SessionEnd::kLocked) << r.error;
  Database db = test::open_or_fail(o.db);
  auto progress = trainee_progress(db, "bob");
  ASSERT_TRUE(progress);
  EXPECT_EQ(progress->size(), 4u);
}

// A view without a window: it watches the live attempt by polling it, and records what the
// session asked of it.
class FakeView final : public AttemptView {
 public:
  bool available = true;
  std::string open_error;          ///< non-empty: open() fails with it
  bool close_window = false;       ///< the trainee closes the window during the attempt
  std::unique_ptr<InputDevice> own;  ///< the view's own device (the mouse, in a real view)
  std::string db_path;             ///< to check the attempt is stored before the score shows

  std::vector<std::string> calls;
  InputDevice* given = nullptr;
  std::string status;
  std::optional<AttemptStatus> status_at_score;

  bool can_open() const override { return available; }
  bool open(const ScenarioModel&, const World& world, InputDevice* device,
            std::string* error) override {
    calls.push_back("open");
    given = device;
    EXPECT_EQ(world.step_count(), 0);  // nothing steps it yet
    if (!open_error.empty()) *error = open_error;
    return open_error.empty();
  }
  InputDevice& device() override { return given ? *given : *own; }
  void watch(LiveAttempt& live) override {
    calls.push_back("watch");
    if (close_window) live.request_stop(AttemptEnd::kStopped);
    LiveView view;
    while (!live.finished()) {
      live.latest(view);
      std::this_thread::sleep_for(2ms);
    }
  }
  void show_score(const AttemptRun& run, const std::string& line) override {
    calls.push_back("score");
    status = line;
    Database db = test::open_or_fail(db_path, OpenOptions{.create = false});
    auto attempts = list_attempts(db);
    if (attempts && !attempts->empty()) status_at_score = attempts->back().status;
  }
};

TEST(AttemptSession, ALiveAttemptIsWatchedThenStoredBeforeItsScoreShows) {
  test::TempDir dir;
  SessionOptions o = replay_options(dir, write_short_trajectory(dir));
  o.checkpoint_every_s = 0.1;
  FakeView view;
  view.db_path = o.db;
  std::ostringstream notes;
  const SessionResult r = run_attempt_session(o, &view, notes);
  ASSERT_EQ(r.end, SessionEnd::kCompleted) << r.error;
  EXPECT_EQ(view.calls, (std::vector<std::string>{"open", "watch", "score"}));
  ASSERT_NE(view.given, nullptr);  // the replay, opened by the session
  EXPECT_EQ(view.status, "Stored as attempt " + std::to_string(r.attempt_id) + " (completed)");
  EXPECT_EQ(view.status_at_score, AttemptStatus::kCompleted);
  EXPECT_NEAR(r.world->time_s(), 0.3, 0.01);
  ASSERT_TRUE(r.haptics);
  EXPECT_GT(r.haptics->loop.ticks, 0);
  EXPECT_FALSE(r.haptics->decoupled);  // a replay steps on one thread
  ASSERT_TRUE(r.checkpoints);
  EXPECT_EQ(r.checkpoints->every_s, 0.1);
  EXPECT_GE(r.checkpoints->stats.saved + r.checkpoints->stats.deferred, 1);
}

TEST(AttemptSession, TheViewDrivesTheMouseInput) {
  test::TempDir dir;
  SessionOptions o = replay_options(dir, "");
  o.input = "mouse";
  FakeView view;
  view.db_path = o.db;
  std::string error;
  view.own = open_input("replay:" + write_short_trajectory(dir), &error);
  ASSERT_TRUE(view.own) << error;
  std::ostringstream notes;
  const SessionResult r = run_attempt_session(o, &view, notes);
  ASSERT_EQ(r.end, SessionEnd::kCompleted) << r.error;
  EXPECT_EQ(view.given, nullptr);  // the session opened no device
  EXPECT_EQ(stored(o.db, r.attempt_id).input_device, "mouse");
}

TEST(AttemptSession, ClosingTheWindowStoresTheAttemptAsAborted) {
  test::TempDir dir;
  SessionOptions o = replay_options(dir, write_short_trajectory(dir));
  FakeView view;
  view.db_path = o.db;
  view.close_window = true;
  std::ostringstream notes;
  const SessionResult r = run_attempt_session(o, &view, notes);
  EXPECT_EQ(r.end, SessionEnd::kAbandoned);
  EXPECT_EQ(r.stored_as, "aborted");
  EXPECT_EQ(view.calls, (std::vector<std::string>{"open", "watch"}));  // no score screen
  const AttemptRecord a = stored(o.db, r.attempt_id);
  EXPECT_EQ(a.status, AttemptStatus::kAborted);
  EXPECT_EQ(a.abort_reason, "stopped before the end by the trainee");
}

TEST(AttemptSession, WithoutADisplayTheAttemptRunsHeadless) {
  test::TempDir dir;
  SessionOptions o = replay_options(dir, write_short_trajectory(dir));
  FakeView view;
  view.available = false;
  std::ostringstream notes;
  const SessionResult r = run_attempt_session(o, &view, notes);
  ASSERT_EQ(r.end, SessionEnd::kCompleted) << r.error;
  EXPECT_EQ(notes.str(), "note: no display, running headless\n");
  EXPECT_TRUE(view.calls.empty());
  EXPECT_FALSE(r.haptics);
  // The mouse, though, cannot do without one.
  o.input = "mouse";
  const SessionResult m = run_attempt_session(o, &view, notes);
  EXPECT_EQ(m.end, SessionEnd::kBadInput);
  EXPECT_NE(m.error.find("there is no display"), std::string::npos) << m.error;
}

TEST(AttemptSession, AWindowThatFailsAbortsTheAttemptAndSaysWhy) {
  test::TempDir dir;
  SessionOptions o = replay_options(dir, write_short_trajectory(dir));
  FakeView view;
  view.open_error = "no GL 3.3";
  std::ostringstream notes;
  const SessionResult r = run_attempt_session(o, &view, notes);
  EXPECT_EQ(r.end, SessionEnd::kBadInput);
  EXPECT_EQ(r.error, "cannot open the trainee view: no GL 3.3");
  const AttemptRecord a = stored(o.db, r.attempt_id);
  EXPECT_EQ(a.status, AttemptStatus::kAborted);
  EXPECT_EQ(a.abort_reason, "window failed: no GL 3.3");
}

}  // namespace
}  // namespace acdr
