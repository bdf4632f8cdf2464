// Shared helpers of the db tests: a temporary directory, a registered curriculum of modules,
// and attempts with a given outcome. Shared, never copied between test files.
#pragma once

#include <gtest/gtest.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "assessment/metrics.hpp"
#include "assessment/recording.hpp"
#include "db/attempt_store.hpp"
#include "db/catalog.hpp"
#include "db/database.hpp"

namespace acdr::test {

/// A fresh directory under $TMPDIR, removed with everything in it at the end of the test.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "acdr-db-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) ADD_FAILURE() << "mkdtemp failed";
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

/// Opens (creating) a record, failing the test with the store's message on error.
inline Database open_or_fail(const std::string& path, const OpenOptions& options = {}) {
  DbResult<Database> db = open_store(path, options);
  if (!db) {
    ADD_FAILURE() << db.error().message;
    return Database();
  }
  return std::move(db.value());
}

/// `PRAGMA integrity_check` of a record: "ok" when intact (a failure is reported otherwise).
inline std::string integrity_check(Database& db) {
  DbResult<Statement> s = db.prepare("PRAGMA integrity_check");
  if (!s.ok()) {
    ADD_FAILURE() << s.error().message;
    return "";
  }
  DbResult<bool> row = s->step();
  if (!row.ok() || !row.value()) {
    ADD_FAILURE() << "integrity_check returned no row";
    return "";
  }
  return s->column_text(0);
}

/// prefix + number, e.g. numbered("m", 2) == "m2". (Appending, not `"m" + std::to_string(i)`:
/// GCC 12 gives a false -Wrestrict warning on that form.)
inline std::string numbered(const char* prefix, int n, const char* suffix = "") {
  std::string out(prefix);
  out += std::to_string(n);
  out += suffix;
  return out;
}

/// Registers curriculum "acdr" with modules "m1".."mN" at positions 1..N (each unlocked by the
/// one before), pass score 50, `required` passes in a row.
inline void register_curriculum(Database& db, int modules, int required = 2) {
  ASSERT_TRUE(upsert_curriculum(db, CurriculumRecord{"acdr", "ACDR scooping"}).ok());
  for (int i = 1; i <= modules; ++i) {
    ModuleRecord m;
    m.id = numbered("m", i);
    m.curriculum_id = "acdr";
    m.position = i;
    m.title = numbered("Module ", i);
    m.scenario_path = numbered("scenarios/modules/m", i, ".json");
    m.scenario_hash = numbered("hash", i);
    m.consecutive_passes_required = required;
    m.pass_score = 50.0;
    DbResult<ModuleRecord> stored = upsert_module(db, m);
    ASSERT_TRUE(stored.ok()) << stored.error().message;
  }
}

/// An outcome with a score, the pass decision, two metrics and one event.
inline AttemptOutcome make_outcome(double score, bool passed) {
  AttemptOutcome o;
  o.metrics.values = {{"nucleus_removed_fraction", score / 100.0},
                      {"peak_instrument_force_N", 3.5}};
  o.score.score = score;
  o.score.passed = passed;
  o.score.terms = {TermScore{"nucleus_removed_fraction", score / 100.0, score}};
  if (!passed) o.score.reasons = {"score below the pass line"};
  o.events = {EventRecord{1.25, "zone_warning", "foramen_left", 0.8, ""}};
  o.duration_s = 12.345;
  o.realtime_factor = 0.85;
  return o;
}

/// Begins and finishes one attempt; started_utc orders attempts in the record. Returns its id.
inline std::int64_t add_attempt(Database& db, const std::optional<std::string>& trainee,
                                const std::string& module, double score, bool passed,
                                const std::string& started_utc) {
  AttemptStart start;
  start.trainee_id = trainee;
  start.module_id = module;
  start.input_device = "replay:demo.csv";
  start.program_version = "0.1.0";
  start.scenario_hash = "hash";
  start.started_utc = started_utc;
  DbResult<std::int64_t> id = begin_attempt(db, start);
  if (!id) {
    ADD_FAILURE() << id.error().message;
    return 0;
  }
  AttemptOutcome outcome = make_outcome(score, passed);
  outcome.ended_utc = started_utc;
  if (DbStatus s = finish_attempt(db, id.value(), outcome); !s) ADD_FAILURE() << s.error().message;
  return id.value();
}

/// "2024-05-01T09:MM:00.000Z" for minute `n` (0..59): increasing start times.
inline std::string minute(int n) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "2024-05-01T09:%02d:00.000Z", n);
  return buffer;
}

/// A child process that kill_when_ready killed (or that exited before it was ready).
struct KilledChild {
  pid_t pid = -1;
  bool was_ready = false;  ///< the child said it was ready before it was killed
  int status = 0;          ///< its wait status
};

/// Forks a child that runs `body(ready_fd)`: it writes one byte to ready_fd when it is where the
/// test wants it killed, and goes on working (it never returns). Waits for that byte, lets the
/// child go on for `extra`, kills it with SIGKILL and reaps it. Open no database connection
/// across the fork.
template <class Body>
KilledChild kill_when_ready(Body body, std::chrono::milliseconds extra = {}) {
  KilledChild out;
  int fds[2];
  if (pipe(fds) != 0) {
    ADD_FAILURE() << "pipe failed";
    return out;
  }
  out.pid = fork();
  if (out.pid < 0) {
    ADD_FAILURE() << "fork failed";
    return out;
  }
  if (out.pid == 0) {
    close(fds[0]);
    body(fds[1]);
    _exit(99);  // the body should never return
  }
  close(fds[1]);
  char ready = 0;
  out.was_ready = read(fds[0], &ready, 1) == 1;
  close(fds[0]);
  if (out.was_ready && extra.count() > 0) std::this_thread::sleep_for(extra);
  kill(out.pid, SIGKILL);
  waitpid(out.pid, &out.status, 0);
  EXPECT_TRUE(out.was_ready) << "child exited early with code "
                             << (WIFEXITED(out.status) ? WEXITSTATUS(out.status) : -1);
  EXPECT_TRUE(WIFSIGNALED(out.status));
  return out;
}

/// The record's one attempt with all its details (a failure is reported when there is not
/// exactly one).
inline AttemptRecord the_only_attempt(Database& db) {
  DbResult<std::vector<AttemptRecord>> attempts =
      list_attempts(db, {}, AttemptDetail{true, true, true});
  if (!attempts) {
    ADD_FAILURE() << attempts.error().message;
    return {};
  }
  if (attempts->size() != 1u) {
    ADD_FAILURE() << attempts->size() << " attempts in the record (expected one)";
    return {};
  }
  return attempts->front();
}

/// An aborted attempt keeps what its checkpoints saved, consistently: a partial recording that
/// decodes, whose recomputed metrics and last frame time are the stored metrics and duration.
/// Returns the decoded recording (empty on failure).
inline AttemptRecording expect_consistent_checkpointed_recording(const AttemptRecord& a) {
  EXPECT_EQ(a.status, AttemptStatus::kAborted);
  if (!a.recording) {
    ADD_FAILURE() << "no recording kept";
    return {};
  }
  EXPECT_FALSE(a.recording->complete);
  std::string error;
  const std::optional<AttemptRecording> decoded = decode_recording(a.recording->bytes, &error);
  if (!decoded) {
    ADD_FAILURE() << error;
    return {};
  }
  EXPECT_EQ(static_cast<std::int64_t>(decoded->frames.size()), a.recording->frame_count);
  // What was recorded and what was measured belong to the same checkpoint.
  EXPECT_EQ(a.metrics.values, compute_metrics(*decoded).values);
  if (!decoded->frames.empty()) {
    EXPECT_EQ(a.duration_s, std::optional<double>(decoded->frames.back().t_s));
  }
  return *decoded;
}

}  // namespace acdr::test
