// Tests of db/attempt_store.cpp: an attempt's round trip, its lifecycle (running -> completed or
// aborted), what survives a writer killed by SIGKILL mid-transaction, and registrations.
#include "db/attempt_store.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <thread>

#include "assessment/metrics.hpp"
#include "assessment/recording.hpp"
#include "db/uuid.hpp"
#include "tests/db/db_test_support.hpp"

namespace acdr {
namespace {

using test::TempDir;

std::vector<std::uint8_t> frame_like_bytes(std::size_t size, unsigned seed) {
  // Regular, slowly varying data like a frame stream, with some noise.
  std::mt19937 rng(seed);
  std::vector<std::uint8_t> bytes(size);
  for (std::size_t i = 0; i < size; ++i) {
    bytes[i] = static_cast<std::uint8_t>((i % 64 < 8) ? rng() : (i / 64) & 0xFF);
  }
  return bytes;
}

AttemptStart practice_start(const std::string& module = "m1") {
  AttemptStart start;
  start.module_id = module;
  start.input_device = "mouse";
  start.program_version = "0.1.0";
  start.scenario_hash = "abc123";
  return start;
}

std::int64_t count_rows(Database& db, const char* sql, std::int64_t id) {
  DbResult<Statement> s = db.prepare(sql);
  EXPECT_TRUE(s.ok());
  EXPECT_TRUE(s->bind_all(id).ok());
  EXPECT_TRUE(s->step().value());
  return s->column_int64(0);
}

TEST(AttemptStore, RoundTripOfAFinishedAttempt) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  test::register_curriculum(db, 1);

  AttemptStart start = practice_start();
  start.trainee_id = "t-0042";
  start.override_lock = true;
  start.override_by = "Dr. Instructor";
  start.override_reason = "repeat after device fault";
  start.started_utc = "2024-05-01T09:30:00.000Z";
  DbResult<std::int64_t> id = begin_attempt(db, start);
  ASSERT_TRUE(id.ok()) << id.error().message;

  AttemptOutcome outcome;
  const double inf = std::numeric_limits<double>::infinity();
  outcome.metrics.values = {{"nucleus_removed_mm3", 123.456789012345},
                            {"nucleus_removed_fraction", 0.4321},
                            {"closest_approach_mm", inf},
                            {"numerical_trouble", std::nan("")},
                            {"a_metric_after", -0.0}};
  outcome.score.score = 71.25;
  outcome.score.passed = false;
  outcome.score.terms = {TermScore{"nucleus_removed_fraction", 0.4321, 66.0}};
  outcome.score.gates = {GateResult{"foramen_impulse_Ns", 2.5, 2.0, false},
                         GateResult{"overload_events", 0.0, 0.0, true}};
  outcome.score.reasons = {"foramen_impulse_Ns 2.5 above 2", "second reason"};
  outcome.events = {EventRecord{0.5, "zone_warning", "foramen_left", 1.75, "entered 2 mm band"},
                    EventRecord{0.75, "overload_warning", "", 0.31, ""},
                    EventRecord{0.75, "numerical", "", 0.0, "stage: solve"}};
  RecordingData recording;
  recording.format = "acdr-frames-v1";
  recording.frame_count = 2000;
  recording.bytes = frame_like_bytes(200000, 7);
  outcome.recording = recording;
  outcome.duration_s = 2.0;
  outcome.ended_utc = "2024-05-01T09:31:02.500Z";
  ASSERT_TRUE(finish_attempt(db, id.value(), outcome).ok());

  DbResult<std::optional<AttemptRecord>> loaded = load_attempt(db, id.value());
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  ASSERT_TRUE(loaded.value().has_value());
  const AttemptRecord& a = *loaded.value();
  EXPECT_EQ(a.status, AttemptStatus::kCompleted);
  EXPECT_EQ(a.trainee_id, std::optional<std::string>("t-0042"));
  EXPECT_EQ(a.module_id, "m1");
  EXPECT_TRUE(is_uuid(a.uuid));
  EXPECT_TRUE(is_uuid(a.registration));
  EXPECT_EQ(a.started_utc, "2024-05-01T09:30:00.000Z");
  EXPECT_EQ(a.ended_utc, std::optional<std::string>("2024-05-01T09:31:02.500Z"));
  EXPECT_EQ(a.duration_s, std::optional<double>(2.0));
  EXPECT_EQ(a.input_device, "mouse");
  EXPECT_EQ(a.program_version, "0.1.0");
  EXPECT_EQ(a.scenario_hash, "abc123");
  EXPECT_TRUE(a.override_lock);
  EXPECT_EQ(a.override_by, "Dr. Instructor");
  EXPECT_EQ(a.override_reason, "repeat after device fault");
  EXPECT_EQ(a.score, std::optional<double>(71.25));
  EXPECT_EQ(a.passed, std::optional<bool>(false));
  EXPECT_EQ(a.writer_pid, static_cast<std::int64_t>(getpid()));

  // Metrics: same order, bit-identical values; NaN survives (SQLite stores it as NULL).
  ASSERT_EQ(a.metrics.values.size(), outcome.metrics.values.size());
  for (std::size_t i = 0; i < a.metrics.values.size(); ++i) {
    EXPECT_EQ(a.metrics.values[i].first, outcome.metrics.values[i].first);
    const double want = outcome.metrics.values[i].second;
    const double got = a.metrics.values[i].second;
    if (std::isnan(want)) {
      EXPECT_TRUE(std::isnan(got));
    } else {
      EXPECT_EQ(got, want) << a.metrics.values[i].first;
    }
  }
  ASSERT_EQ(a.score_detail.terms.size(), 1u);
  EXPECT_EQ(a.score_detail.terms[0].score, 66.0);
  ASSERT_EQ(a.score_detail.gates.size(), 2u);
  EXPECT_FALSE(a.score_detail.gates[0].passed);
  EXPECT_EQ(a.score_detail.gates[0].max, 2.0);
  EXPECT_TRUE(a.score_detail.gates[1].passed);
  EXPECT_EQ(a.score_detail.reasons, outcome.score.reasons);

  ASSERT_EQ(a.events.size(), 3u);
  for (std::size_t i = 0; i < a.events.size(); ++i) {
    EXPECT_EQ(a.events[i].t_s, outcome.events[i].t_s);
    EXPECT_EQ(a.events[i].kind, outcome.events[i].kind);
    EXPECT_EQ(a.events[i].zone, outcome.events[i].zone);
    EXPECT_EQ(a.events[i].value, outcome.events[i].value);
    EXPECT_EQ(a.events[i].detail, outcome.events[i].detail);
  }

  ASSERT_TRUE(a.recording.has_value());
  EXPECT_EQ(a.recording->format, "acdr-frames-v1");
  EXPECT_EQ(a.recording->frame_count, 2000);
  EXPECT_TRUE(a.recording->complete);
  EXPECT_EQ(a.recording->bytes, recording.bytes);
  // Stored compressed: the blob is much smaller than the raw stream.
  const std::int64_t stored =
      count_rows(db, "SELECT length(data) FROM recordings WHERE attempt_id = ?", id.value());
  EXPECT_LT(stored, static_cast<std::int64_t>(recording.bytes.size()) / 2);
}

TEST(AttemptStore, BeginCommitsTheRunningRowAtOnce) {
  TempDir dir;
  const std::string path = dir.file("record.sqlite");
  Database writer = test::open_or_fail(path);
  test::register_curriculum(writer, 1);
  DbResult<std::int64_t> id = begin_attempt(writer, practice_start());
  ASSERT_TRUE(id.ok());
  EXPECT_FALSE(writer.in_transaction());

  // Another connection (the dashboard) sees it running; opening does not abort it, since its
  // writer (this process) is alive.
  Database reader = test::open_or_fail(path);
  DbResult<std::optional<AttemptRecord>> a = load_attempt(reader, id.value());
  ASSERT_TRUE(a.ok());
  ASSERT_TRUE(a.value().has_value());
  EXPECT_EQ(a.value()->status, AttemptStatus::kRunning);
  EXPECT_TRUE(a.value()->is_practice());
  EXPECT_FALSE(a.value()->ended_utc.has_value());
  EXPECT_TRUE(mark_interrupted_attempts(reader).value().empty());
}

TEST(AttemptStore, OnlyARunningAttemptCanBeFinishedCheckpointedOrAborted) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  test::register_curriculum(db, 1);
  const std::int64_t done = test::add_attempt(db, "t1", "m1", 80.0, true, test::minute(0));

  DbStatus again = finish_attempt(db, done, test::make_outcome(10.0, false));
  ASSERT_FALSE(again.ok());
  EXPECT_NE(again.error().message.find("already completed"), std::string::npos)
      << again.error().message;
  EXPECT_FALSE(checkpoint_attempt(db, done, {}, nullptr).ok());
  EXPECT_FALSE(abort_attempt(db, done, "quit").ok());
  EXPECT_EQ(load_attempt(db, done).value()->score, std::optional<double>(80.0));

  DbResult<std::int64_t> quit = begin_attempt(db, practice_start());
  ASSERT_TRUE(abort_attempt(db, quit.value(), "trainee quit").ok());
  EXPECT_EQ(load_attempt(db, quit.value()).value()->status, AttemptStatus::kAborted);
  EXPECT_EQ(load_attempt(db, quit.value()).value()->abort_reason, "trainee quit");
  EXPECT_FALSE(finish_attempt(db, quit.value(), test::make_outcome(90.0, true)).ok());

  EXPECT_FALSE(finish_attempt(db, 9999, test::make_outcome(90.0, true)).ok());
  // The schema itself refuses to reopen a final attempt.
  DbResult<Statement> reopen = db.prepare("UPDATE attempts SET status = 'running' WHERE id = ?");
  ASSERT_TRUE(reopen->bind_all(done).ok());
  EXPECT_FALSE(reopen->run().ok());
}

TEST(AttemptStore, BeginRejectsBadStartsWithClearErrors) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  test::register_curriculum(db, 1);

  DbResult<std::int64_t> unknown = begin_attempt(db, practice_start("no-such-module"));
  ASSERT_FALSE(unknown.ok());
  EXPECT_NE(unknown.error().message.find("no-such-module"), std::string::npos);

  AttemptStart override = practice_start();
  override.trainee_id = "t1";
  override.override_lock = true;
  EXPECT_FALSE(begin_attempt(db, override).ok());

  AttemptStart bad_time = practice_start();
  bad_time.started_utc = "yesterday";
  DbResult<std::int64_t> r = begin_attempt(db, bad_time);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("yesterday"), std::string::npos);
  EXPECT_TRUE(list_attempts(db).value().empty());

  // An unknown trainee is registered on first attempt.
  AttemptStart fresh = practice_start();
  fresh.trainee_id = "new-trainee";
  ASSERT_TRUE(begin_attempt(db, fresh).ok());
  EXPECT_TRUE(find_trainee(db, "new-trainee").value().has_value());
}

TEST(AttemptStore, RegistrationIsSharedPerTraineeAndModule) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  test::register_curriculum(db, 2);
  const auto a1 = test::add_attempt(db, "t1", "m1", 60, true, test::minute(0));
  const auto a2 = test::add_attempt(db, "t1", "m1", 40, false, test::minute(1));
  const auto b1 = test::add_attempt(db, "t1", "m2", 60, true, test::minute(2));
  const auto c1 = test::add_attempt(db, "t2", "m1", 60, true, test::minute(3));
  const auto p1 = test::add_attempt(db, std::nullopt, "m1", 60, true, test::minute(4));
  const auto p2 = test::add_attempt(db, std::nullopt, "m1", 60, true, test::minute(5));
  auto reg = [&](std::int64_t id) { return load_attempt(db, id).value()->registration; };
  EXPECT_EQ(reg(a1), reg(a2));
  EXPECT_NE(reg(a1), reg(b1));
  EXPECT_NE(reg(a1), reg(c1));
  EXPECT_NE(reg(p1), reg(p2));
  EXPECT_NE(load_attempt(db, a1).value()->uuid, load_attempt(db, a2).value()->uuid);
}

TEST(AttemptStore, ListFiltersByTraineeModuleAndPractice) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  test::register_curriculum(db, 2);
  test::add_attempt(db, "t1", "m1", 60, true, test::minute(3));
  test::add_attempt(db, "t1", "m2", 60, true, test::minute(1));
  test::add_attempt(db, "t2", "m1", 60, true, test::minute(2));
  test::add_attempt(db, std::nullopt, "m1", 60, true, test::minute(0));

  auto ids = [&](const AttemptFilter& f) {
    std::vector<std::string> out;
    for (const AttemptRecord& a : list_attempts(db, f).value()) {
      out.push_back(a.trainee_id.value_or("-") + "/" + a.module_id);
    }
    return out;
  };
  EXPECT_EQ(ids({}), (std::vector<std::string>{"-/m1", "t1/m2", "t2/m1", "t1/m1"}));
  EXPECT_EQ(ids({"t1", std::nullopt, true}), (std::vector<std::string>{"t1/m2", "t1/m1"}));
  EXPECT_EQ(ids({std::nullopt, "m1", true}), (std::vector<std::string>{"-/m1", "t2/m1", "t1/m1"}));
  EXPECT_EQ(ids({std::nullopt, "m1", false}), (std::vector<std::string>{"t2/m1", "t1/m1"}));
  EXPECT_EQ(ids({"t1", "m1", true}), (std::vector<std::string>{"t1/m1"}));
}

TEST(AttemptStore, RescoreReplacesMetricsAndScoreOnly) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  test::register_curriculum(db, 1);
  const auto id = test::add_attempt(db, "t1", "m1", 40, false, test::minute(0));
  AttemptOutcome newer = test::make_outcome(75, true);
  newer.metrics.values.emplace_back("new_metric", 1.5);
  ASSERT_TRUE(update_attempt_assessment(db, id, newer.metrics, newer.score).ok());
  const AttemptRecord a = *load_attempt(db, id).value();
  EXPECT_EQ(a.score, std::optional<double>(75));
  EXPECT_EQ(a.passed, std::optional<bool>(true));
  EXPECT_EQ(a.metrics.values.size(), 3u);
  EXPECT_TRUE(a.score_detail.reasons.empty());
  EXPECT_EQ(a.events.size(), 1u);
  EXPECT_EQ(a.status, AttemptStatus::kCompleted);
}

TEST(AttemptStore, AnAbortedAttemptGetsNewMetricsButNeverAScore) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  test::register_curriculum(db, 1);
  const auto id = begin_attempt(db, practice_start()).value();
  AttemptCheckpoint checkpoint;
  checkpoint.metrics = Metrics{{{"tip_path_length_mm", 3.0}}};
  checkpoint.duration_s = 1.0;
  ASSERT_TRUE(append_checkpoint(db, id, checkpoint).ok());
  // Only an aborted attempt: a running or completed one keeps its metrics.
  EXPECT_FALSE(update_aborted_metrics(db, id, Metrics{{{"tip_path_length_mm", 4.0}}}).ok());
  ASSERT_TRUE(abort_attempt(db, id, "stopped").ok());
  ASSERT_TRUE(update_aborted_metrics(db, id, Metrics{{{"tip_path_length_mm", 4.0}}}).ok());
  const AttemptRecord a = *load_attempt(db, id).value();
  EXPECT_EQ(a.status, AttemptStatus::kAborted);
  EXPECT_EQ(a.metrics.values, (Metrics{{{"tip_path_length_mm", 4.0}}}.values));
  EXPECT_FALSE(a.score.has_value());
  EXPECT_FALSE(a.passed.has_value());
  EXPECT_TRUE(a.score_detail.terms.empty());
  EXPECT_EQ(a.duration_s, std::optional<double>(1.0));
  // And a completed attempt is re-scored with update_attempt_assessment, not this.
  const auto done = test::add_attempt(db, "t1", "m1", 40, false, test::minute(0));
  EXPECT_FALSE(update_aborted_metrics(db, done, Metrics{}).ok());
}

TEST(AttemptStore, AttemptOfAWriterOnAnotherHostIsAbortedButOwnIsNot) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  test::register_curriculum(db, 1);
  const auto other_host = begin_attempt(db, practice_start()).value();
  const auto mine = begin_attempt(db, practice_start()).value();
  const std::vector<EventRecord> events = {EventRecord{0.1, "zone_warning", "artery", 1.0, ""}};
  ASSERT_TRUE(checkpoint_attempt(db, other_host, events, nullptr).ok());

  DbResult<Statement> s = db.prepare(
      "UPDATE attempts SET writer_host = 'elsewhere/another-boot' WHERE id = ?");
  ASSERT_TRUE(s->bind_all(other_host).ok());
  ASSERT_TRUE(s->run().ok());

  DbResult<std::vector<std::int64_t>> aborted = mark_interrupted_attempts(db);
  ASSERT_TRUE(aborted.ok());
  EXPECT_EQ(aborted.value(), std::vector<std::int64_t>{other_host});
  const AttemptRecord a = *load_attempt(db, other_host).value();
  EXPECT_EQ(a.status, AttemptStatus::kAborted);
  EXPECT_EQ(a.ended_utc, std::optional<std::string>(a.heartbeat_utc));
  EXPECT_NE(a.abort_reason.find("elsewhere"), std::string::npos);
  EXPECT_EQ(a.events.size(), 1u);  // what was checkpointed stays
  EXPECT_EQ(load_attempt(db, mine).value()->status, AttemptStatus::kRunning);
}

// Child process body: begin an attempt, checkpoint it, then open a transaction that finishes
// the attempt but never commits; tell the parent and wait to be killed.
[[noreturn]] void child_killed_mid_transaction(const std::string& path, int ready_fd) {
  DbResult<Database> db = open_store(path);
  if (!db) _exit(10);
  DbResult<std::int64_t> id = begin_attempt(db.value(), [] {
    AttemptStart s;
    s.trainee_id = "t1";
    s.module_id = "m1";
    s.input_device = "replay:novice.csv";
    return s;
  }());
  if (!id) _exit(11);
  const std::vector<EventRecord> early = {EventRecord{0.5, "zone_warning", "foramen", 2.0, ""},
                                          EventRecord{0.9, "overload_warning", "", 0.4, ""}};
  RecordingData partial;
  partial.format = "acdr-frames-v1";
  partial.frame_count = 900;
  partial.bytes = frame_like_bytes(90000, 1);
  if (!checkpoint_attempt(db.value(), id.value(), early, &partial)) _exit(12);

  DbResult<Transaction> tx = Transaction::begin(db.value());
  if (!tx) _exit(13);
  AttemptOutcome outcome = test::make_outcome(90.0, true);
  RecordingData full = partial;
  full.frame_count = 5000;
  full.bytes = frame_like_bytes(500000, 2);
  outcome.recording = full;
  if (!finish_attempt(db.value(), id.value(), outcome)) _exit(14);
  const char ready = 'R';
  if (write(ready_fd, &ready, 1) != 1) _exit(15);
  for (;;) pause();
}

TEST(AttemptStore, WriterKilledMidTransactionLeavesAnIntactRecordAndAnAbortedAttempt) {
  TempDir dir;
  const std::string path = dir.file("record.sqlite");
  {
    Database db = test::open_or_fail(path);
    test::register_curriculum(db, 1);
  }  // no connection open across fork()
  const test::KilledChild killed =
      test::kill_when_ready([&](int ready_fd) { child_killed_mid_transaction(path, ready_fd); });
  ASSERT_TRUE(killed.was_ready);
  const pid_t child = killed.pid;

  // The next program to open the record finds the attempt's writer gone.
  Database db = test::open_or_fail(path);
  EXPECT_EQ(test::integrity_check(db), "ok");
  const AttemptRecord a = test::the_only_attempt(db);
  EXPECT_EQ(a.status, AttemptStatus::kAborted);
  EXPECT_NE(a.abort_reason.find(std::to_string(child)), std::string::npos) << a.abort_reason;
  EXPECT_EQ(a.writer_pid, static_cast<std::int64_t>(child));
  // Nothing of the uncommitted finish; everything of the committed checkpoint.
  EXPECT_FALSE(a.score.has_value());
  EXPECT_TRUE(a.metrics.values.empty());
  ASSERT_EQ(a.events.size(), 2u);
  EXPECT_EQ(a.events[0].zone, "foramen");
  ASSERT_TRUE(a.recording.has_value());
  EXPECT_FALSE(a.recording->complete);
  EXPECT_EQ(a.recording->frame_count, 900);
  EXPECT_EQ(a.recording->bytes, frame_like_bytes(90000, 1));
  // And the record still takes new attempts.
  EXPECT_NE(test::add_attempt(db, "t1", "m1", 70, true, test::minute(59)), 0);
}

TEST(AttemptStore, KillDuringARealFinishIsAllOrNothing) {
  TempDir dir;
  const std::string path = dir.file("record.sqlite");
  {
    Database db = test::open_or_fail(path);
    test::register_curriculum(db, 1);
  }
  // Kill at several moments of a finish that writes a few MB; whichever moment it is, the
  // attempt is either completed with everything or aborted with nothing of the finish.
  const int delays_ms[] = {0, 5, 20, 60};
  for (int delay : delays_ms) {
    int pipe_fds[2];
    ASSERT_EQ(pipe(pipe_fds), 0);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      close(pipe_fds[0]);
      DbResult<Database> db = open_store(path);
      if (!db) _exit(10);
      AttemptStart s;
      s.trainee_id = "t1";
      s.module_id = "m1";
      DbResult<std::int64_t> id = begin_attempt(db.value(), s);
      if (!id) _exit(11);
      const char began = 'B';
      if (write(pipe_fds[1], &began, 1) != 1) _exit(12);
      AttemptOutcome outcome = test::make_outcome(66.0, true);
      outcome.events.assign(2000, EventRecord{1.0, "contact", "endplate", 0.5, "x"});
      RecordingData r;
      r.format = "acdr-frames-v1";
      r.frame_count = 30000;
      r.bytes = frame_like_bytes(3000000, 3);
      outcome.recording = r;
      if (!finish_attempt(db.value(), id.value(), outcome)) _exit(13);
      for (;;) pause();
    }
    close(pipe_fds[1]);
    char began = 0;
    const ssize_t got = read(pipe_fds[0], &began, 1);
    close(pipe_fds[0]);
    if (got != 1) {
      int status = 0;
      waitpid(child, &status, 0);
      FAIL() << "child exited before beginning, code "
             << (WIFEXITED(status) ? WEXITSTATUS(status) : -1) << " (delay " << delay << ")";
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(delay));
    kill(child, SIGKILL);
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
  }
  Database db = test::open_or_fail(path);
  EXPECT_EQ(test::integrity_check(db), "ok");
  DbResult<std::vector<AttemptRecord>> attempts =
      list_attempts(db, {}, AttemptDetail{true, true, true});
  ASSERT_TRUE(attempts.ok()) << attempts.error().message;
  ASSERT_EQ(attempts->size(), std::size(delays_ms));
  for (const AttemptRecord& a : attempts.value()) {
    if (a.status == AttemptStatus::kCompleted) {
      EXPECT_EQ(a.metrics.values.size(), 2u);
      EXPECT_EQ(a.events.size(), 2000u);
      ASSERT_TRUE(a.recording.has_value());
      EXPECT_EQ(a.recording->bytes.size(), 3000000u);
    } else {
      EXPECT_EQ(a.status, AttemptStatus::kAborted);
      EXPECT_TRUE(a.metrics.values.empty());
      EXPECT_TRUE(a.events.empty());
      EXPECT_FALSE(a.recording.has_value());
    }
  }
}

// --- checkpoints (append_checkpoint) ----------------------------------------------------------

// A synthetic attempt near one never-event zone: frame i at t = (i + 1) ms, the tip moving
// along x, within the warning band for frames 300..399.
Frame checkpoint_frame(int i) {
  Frame f;
  f.t_s = (i + 1) * 1e-3;
  f.tip_m = Vec3(1e-5 * i, 2e-3 * std::sin(1e-3 * i), 0.0);
  f.nucleus_force_N = Vec3(0.0, 0.1, 0.2 + 1e-4 * (i % 97));
  f.bending_moment_Nm = 1e-3 * (i % 50);
  f.removed_target = i / 3;
  f.zone_count = 1;
  const bool near = i % 1000 >= 300 && i % 1000 < 400;
  f.zones[0] = {near ? 1e-3f : 4e-3f, near ? 0.5f : 0.0f, false, near};
  return f;
}

WorldSummary checkpoint_summary() {
  WorldSummary s;
  s.dt_s = 1e-3;
  s.particle_volume_m3 = 1e-9;
  s.initial_target = 5000;
  s.zones = {{"spinal_cord_pll", 2e-3, 1.0, true}};
  return s;
}

// The checkpoint of frames [from, to) as a running attempt writes it: the recording piece
// (with the header before the first frames), the events of those frames, the metrics so far.
AttemptCheckpoint make_checkpoint(AttemptRecording& so_far, int from, int to) {
  AttemptCheckpoint c;
  RecordingData chunk;
  chunk.format = kRecordingFormat;
  if (from == 0) chunk.bytes = encode_recording_header(so_far.summary);
  const std::size_t first_event = so_far.events.size();
  for (int i = from; i < to; ++i) {
    so_far.frames.push_back(checkpoint_frame(i));
    if (i % 1000 == 300) {
      Event e{(i + 1) * 1e-3, EventKind::kZoneWarning, 1e-3, "spinal_cord_pll"};
      e.zone = 0;
      so_far.events.push_back(e);
      c.new_events.push_back(EventRecord{e.t_s, "zone_warning", "spinal_cord_pll", e.value, "", 0});
    }
    if (i % 1000 == 500) {
      so_far.events.push_back(Event{(i + 1) * 1e-3, EventKind::kOverloadWarning, 0.2, ""});
      c.new_events.push_back(EventRecord{(i + 1) * 1e-3, "overload_warning", "", 0.2, ""});
    }
  }
  append_frame_block(std::span(so_far.frames).subspan(static_cast<std::size_t>(from)), chunk.bytes);
  append_event_block(std::span(so_far.events).subspan(first_event), chunk.bytes);
  chunk.frame_count = to - from;
  chunk.complete = false;
  c.chunk = std::move(chunk);
  c.metrics = compute_metrics(so_far);
  c.duration_s = so_far.frames.back().t_s;
  return c;
}

TEST(AttemptStore, CheckpointsAppendEventsAndRecordingPiecesAndKeepMetricsSoFar) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  test::register_curriculum(db, 1);
  const std::int64_t id = begin_attempt(db, practice_start()).value();
  AttemptRecording so_far;
  so_far.summary = checkpoint_summary();
  for (int k = 0; k < 3; ++k) {
    ASSERT_TRUE(append_checkpoint(db, id, make_checkpoint(so_far, 1000 * k, 1000 * (k + 1))).ok());
  }
  EXPECT_EQ(count_rows(db, "SELECT count(*) FROM recording_chunks WHERE attempt_id = ?", id), 3);

  AttemptRecord a = *load_attempt(db, id).value();
  EXPECT_EQ(a.status, AttemptStatus::kRunning);
  EXPECT_EQ(a.duration_s, std::optional<double>(3.0));
  ASSERT_EQ(a.events.size(), 6u);  // a warning and an overload per checkpoint, in order
  EXPECT_EQ(a.events[2].kind, "zone_warning");
  EXPECT_EQ(a.events[2].zone, "spinal_cord_pll");
  EXPECT_EQ(a.events[2].zone_index, 0);
  EXPECT_EQ(a.events[3].zone, "");
  EXPECT_EQ(a.events[3].zone_index, -1);
  // Not about a zone: NULL in the table, not ''.
  EXPECT_EQ(count_rows(db, "SELECT count(*) FROM events WHERE attempt_id = ? AND zone IS NULL "
                           "AND zone_index IS NULL", id), 3);
  ASSERT_TRUE(a.recording.has_value());
  EXPECT_FALSE(a.recording->complete);
  EXPECT_EQ(a.recording->format, kRecordingFormat);
  EXPECT_EQ(a.recording->frame_count, 3000);
  std::string error;
  const auto decoded = decode_recording(a.recording->bytes, &error);
  ASSERT_TRUE(decoded) << error;
  EXPECT_EQ(decoded->frames.size(), 3000u);
  EXPECT_EQ(decoded->events.size(), 6u);
  // The stored metrics are those of the stored recording, exactly.
  EXPECT_EQ(a.metrics.values, compute_metrics(*decoded).values);
  EXPECT_EQ(*a.metrics.find("zone.spinal_cord_pll.warnings"), 3.0);
  EXPECT_FALSE(a.score.has_value());

  // Finishing replaces the pieces with the whole recording, and all events.
  AttemptOutcome outcome = test::make_outcome(75.0, true);
  outcome.events = a.events;
  outcome.recording = RecordingData{kRecordingFormat, 3000, encode_recording(so_far), true};
  ASSERT_TRUE(finish_attempt(db, id, outcome).ok());
  EXPECT_EQ(count_rows(db, "SELECT count(*) FROM recording_chunks WHERE attempt_id = ?", id), 0);
  a = *load_attempt(db, id).value();
  ASSERT_TRUE(a.recording.has_value());
  EXPECT_TRUE(a.recording->complete);
  EXPECT_EQ(decode_recording(a.recording->bytes, &error)->frames.size(), 3000u);
  EXPECT_EQ(a.events.size(), 6u);
  EXPECT_FALSE(append_checkpoint(db, id, AttemptCheckpoint{}).ok());  // no longer running
}

// Child body: an attempt checkpointed every 500 frames for ever; says "ready" after the
// fourth checkpoint, and is killed by the parent some time later (maybe mid-transaction).
[[noreturn]] void child_checkpointing_until_killed(const std::string& path, int ready_fd) {
  DbResult<Database> db = open_store(path);
  if (!db) _exit(10);
  AttemptStart start = practice_start();
  start.trainee_id = "t1";
  DbResult<std::int64_t> id = begin_attempt(db.value(), start);
  if (!id) _exit(11);
  AttemptRecording so_far;
  so_far.summary = checkpoint_summary();
  for (int k = 0;; ++k) {
    if (!append_checkpoint(db.value(), id.value(), make_checkpoint(so_far, 500 * k, 500 * (k + 1))))
      _exit(12);
    if (k == 3) {
      const char ready = 'R';
      if (write(ready_fd, &ready, 1) != 1) _exit(13);
    }
  }
}

TEST(AttemptStore, SigkillMidAttemptLeavesAnAbortedAttemptWithItsCheckpointedRecording) {
  TempDir dir;
  const std::string path = dir.file("record.sqlite");
  {
    Database db = test::open_or_fail(path);
    test::register_curriculum(db, 1);
  }  // no connection open across fork()
  // Killed a little after its fourth checkpoint, as it writes more.
  const test::KilledChild killed =
      test::kill_when_ready([&](int ready_fd) { child_checkpointing_until_killed(path, ready_fd); },
                            std::chrono::milliseconds(30));
  ASSERT_TRUE(killed.was_ready);

  Database db = test::open_or_fail(path);  // the next start marks the attempt aborted
  EXPECT_EQ(test::integrity_check(db), "ok");
  const AttemptRecord a = test::the_only_attempt(db);
  ASSERT_TRUE(a.recording.has_value());
  EXPECT_GE(a.recording->frame_count, 2000);
  EXPECT_EQ(a.recording->frame_count % 500, 0);  // whole checkpoints only
  const AttemptRecording decoded = test::expect_consistent_checkpointed_recording(a);
  EXPECT_EQ(a.events.size(), decoded.events.size());
}

}  // namespace
}  // namespace acdr
