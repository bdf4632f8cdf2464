// End to end with the acdr program: `acdr run` killed by SIGKILL
// mid-attempt leaves an intact record, and the next start (`acdr report`) shows the attempt
// aborted with the recording and the metrics of its last checkpoint, which agree exactly — for
// a headless replay and for a live attempt over the UDP bridge; a completed attempt re-scored
// by `acdr rescore` reproduces its stored metrics exactly, an aborted one its checkpointed ones.
#include <gtest/gtest.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/mount.h>
#include <sys/socket.h>
#include <sys/statvfs.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "assessment/metrics.hpp"
#include "assessment/recording.hpp"
#include "tests/db/db_test_support.hpp"

namespace acdr {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A long replay for the small test box: the short scoop forth and back, `legs` times.
void write_long_trajectory(const std::string& source, const std::string& out_path, int legs) {
  std::ifstream in(source);
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || !(std::isdigit(static_cast<unsigned char>(line[0])) || line[0] == '-')) {
      header.push_back(line);
      continue;
    }
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  const double period = std::stod(rows.back()[0]);
  std::ofstream out(out_path);
  for (const std::string& h : header) out << h << "\n";
  for (int leg = 0; leg < legs; ++leg) {
    for (std::size_t k = (leg == 0 ? 0 : 1); k < rows.size(); ++k) {
      const std::size_t i = leg % 2 == 0 ? k : rows.size() - 1 - k;
      const double t = leg * period + (leg % 2 == 0 ? std::stod(rows[i][0])
                                                    : period - std::stod(rows[i][0]));
      char time[32];
      std::snprintf(time, sizeof time, "%.6f", t);
      out << time;
      for (std::size_t c = 1; c < rows[i].size(); ++c) out << "," << rows[i][c];
      out << "\n";
    }
  }
}

// Chunks committed so far, read without marking anything (a plain read-only connection).
int committed_chunks(const std::string& db_path) {
  sqlite3* db = nullptr;
  int n = -1;
  if (sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_busy_timeout(db, 1000);
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT count(*) FROM recording_chunks", -1, &s, nullptr) ==
            SQLITE_OK &&
        sqlite3_step(s) == SQLITE_ROW) {
      n = sqlite3_column_int(s, 0);
    }
    sqlite3_finalize(s);
  }
  sqlite3_close(db);
  return n;
}

// Waits (up to 60 s) until `n` recording chunks of a running child are committed; true if the
// child exited first (its wait status in *status).
bool exited_before_chunks(const std::string& db_path, pid_t child, int n, int* status) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (committed_chunks(db_path) < n && std::chrono::steady_clock::now() < deadline) {
    if (waitpid(child, status, WNOHANG) == child) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

// The small test box with room for a long replay; returns the scene file's path.
std::string write_scene(const test::TempDir& dir) {
  nlohmann::json scene = nlohmann::json::parse(
      read_text(std::string(ACDR_SOURCE_DIR) + "/tests/ui/data/small_box.json"));
  scene["time_limit_s"] = 60;
  const std::string path = dir.file("scene.json");
  std::ofstream(path) << scene.dump(2);
  return path;
}

// Runs `command`, returns its stdout; fails the test on a non-zero exit.
std::string run_program(const std::string& command) {
  FILE* pipe = popen(command.c_str(), "r");
  EXPECT_NE(pipe, nullptr);
  if (!pipe) return {};
  std::string output;
  char buffer[4096];
  for (std::size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) output.append(buffer, n);
  EXPECT_EQ(pclose(pipe), 0) << command << "\n" << output;
  return output;
}

TEST(AcdrRunRecord, KilledAttemptIsAbortedWithItsCheckpointedRecordingAndMetrics) {
  test::TempDir dir;
  const std::string db_path = dir.file("record.sqlite");
  const std::string trajectory = dir.file("long.csv");
  write_long_trajectory(std::string(ACDR_SOURCE_DIR) + "/tests/ui/data/short_scoop.csv",
                        trajectory, 3);
  const std::string scene_path = write_scene(dir);

  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    if (!freopen("/dev/null", "w", stdout)) _exit(120);
    execl(ACDR_EXE, ACDR_EXE, "run", scene_path.c_str(), "--input",
          ("replay:" + trajectory).c_str(), "--headless", "--db", db_path.c_str(),
          "--checkpoint-every", "0.1", "--trainee", "t-kill", static_cast<char*>(nullptr));
    _exit(127);
  }
  // Kill it once a few checkpoints are committed.
  int status = 0;
  const bool exited = exited_before_chunks(db_path, child, 3, &status);
  ASSERT_FALSE(exited) << "acdr run ended before it was killed (exit "
                       << (WIFEXITED(status) ? WEXITSTATUS(status) : -1) << ")";
  ASSERT_EQ(kill(child, SIGKILL), 0);
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status));

  // The next start of the program: `acdr report` shows the attempt aborted.
  const std::string output =
      run_program(std::string(ACDR_EXE) + " report --db '" + db_path + "' --format json");
  const nlohmann::json report = nlohmann::json::parse(output);
  ASSERT_EQ(report["attempts"].size(), 1u) << output;
  EXPECT_EQ(report["attempts"][0]["status"], "aborted");

  Database db = test::open_or_fail(db_path);
  EXPECT_EQ(test::integrity_check(db), "ok");
  const AttemptRecord a = test::the_only_attempt(db);
  const AttemptRecording decoded = test::expect_consistent_checkpointed_recording(a);
  ASSERT_GE(decoded.frames.size(), 300u);  // at least three 0.1 s checkpoints at 1 kHz
  EXPECT_GT(*a.metrics.find("tip_path_length_mm"), 0.0);
}

// A UDP port on loopback that is free right now (bound to port 0, read back, released).
int free_udp_port() {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) return 0;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof addr;
  int port = 0;
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
      getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0)
    port = ntohs(addr.sin_port);
  close(fd);
  return port;
}

// Starts `argv` as a child with stdout (and stderr, when `quiet`) to /dev/null.
pid_t spawn(const std::vector<std::string>& argv, bool quiet) {
  const pid_t child = fork();
  if (child != 0) return child;
  if (!freopen("/dev/null", "w", stdout)) _exit(120);
  if (quiet && !freopen("/dev/null", "w", stderr)) _exit(120);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  execv(args[0], args.data());
  _exit(127);
}

// A live attempt (the UDP bridge, `acdr device-sim` as the device) checkpoints on its
// writer thread; killed with SIGKILL mid-attempt, it leaves an intact record in which the next
// start shows it aborted with the frames, events and metrics of its last checkpoint, and
// `acdr rescore` re-computes exactly those metrics from its recording while it stays aborted.
TEST(AcdrRunRecord, KilledLiveAttemptIsAbortedWithItsCheckpointsAndRescoresToThem) {
  test::TempDir dir;
  const std::string db_path = dir.file("record.sqlite");
  const std::string trajectory = dir.file("long.csv");
  write_long_trajectory(std::string(ACDR_SOURCE_DIR) + "/tests/ui/data/short_scoop.csv",
                        trajectory, 3);  // 9 s: far longer than the run is let live
  const std::string scene_path = write_scene(dir);
  const int port = free_udp_port();
  ASSERT_GT(port, 0);

  const pid_t run = spawn({ACDR_EXE, "run", scene_path, "--input",
                           "udp:" + std::to_string(port), "--headless", "--db", db_path,
                           "--checkpoint-every", "0.2", "--device-timeout", "20", "--trainee",
                           "t-live"},
                          false);
  ASSERT_GT(run, 0);
  const pid_t bridge = spawn({ACDR_EXE, "device-sim", "--port", std::to_string(port),
                              "--trajectory", trajectory, "--connect-timeout", "20",
                              "--peer-timeout", "1",
                              "--nan-at", "0.15"},  // a rejected pose: an event to keep
                             true);
  ASSERT_GT(bridge, 0);
  // Kill the run once three checkpoints are committed.
  int status = 0;
  const bool exited = exited_before_chunks(db_path, run, 3, &status);
  if (!exited) {
    ASSERT_EQ(kill(run, SIGKILL), 0);
    ASSERT_EQ(waitpid(run, &status, 0), run);
  }
  // The device notices that its simulator is gone (no force for its 1 s peer timeout) and
  // says so with exit code 1, instead of playing on as if connected.
  int bridge_status = 0;
  bool bridge_exited = false;
  for (auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(15);
       !bridge_exited && std::chrono::steady_clock::now() < give_up;
       std::this_thread::sleep_for(std::chrono::milliseconds(20)))
    bridge_exited = waitpid(bridge, &bridge_status, WNOHANG) == bridge;
  if (!bridge_exited) {
    kill(bridge, SIGKILL);  // our own child
    waitpid(bridge, nullptr, 0);
  }
  EXPECT_TRUE(bridge_exited) << "device-sim played on after its simulator was killed";
  if (bridge_exited) {
    EXPECT_TRUE(WIFEXITED(bridge_status));
    EXPECT_EQ(WEXITSTATUS(bridge_status), 1) << "device-sim should report the lost simulator";
  }
  ASSERT_FALSE(exited) << "acdr run ended before it was killed (exit "
                       << (WIFEXITED(status) ? WEXITSTATUS(status) : -1) << ")";
  ASSERT_TRUE(WIFSIGNALED(status));

  // The next start of the program: `acdr report` shows the attempt aborted.
  const std::string output =
      run_program(std::string(ACDR_EXE) + " report --db '" + db_path + "' --format json");
  const nlohmann::json report = nlohmann::json::parse(output);
  ASSERT_EQ(report["attempts"].size(), 1u) << output;
  const nlohmann::json& shown = report["attempts"][0];
  EXPECT_EQ(shown["status"], "aborted");
  EXPECT_GT(shown["duration_s"].get<double>(), 0.0);
  EXPECT_FALSE(shown["metrics"].empty());
  EXPECT_TRUE(shown["score"].is_null());
  EXPECT_TRUE(shown["passed"].is_null());

  AttemptRecord a;
  {
    Database db = test::open_or_fail(db_path);
    EXPECT_EQ(test::integrity_check(db), "ok");
    a = test::the_only_attempt(db);
  }
  EXPECT_EQ(a.input_device, "udp:" + std::to_string(port));
  const AttemptRecording decoded = test::expect_consistent_checkpointed_recording(a);
  // At least three 0.2 s checkpoints of the 1 ms step, each ending on its own step.
  ASSERT_GE(decoded.frames.size(), 600u);
  for (std::size_t i = 1; i < decoded.frames.size(); ++i)
    ASSERT_GT(decoded.frames[i].t_s, decoded.frames[i - 1].t_s) << i;
  ASSERT_TRUE(a.duration_s.has_value());
  EXPECT_GT(*a.duration_s, 0.0);
  EXPECT_GT(*a.metrics.find("tip_path_length_mm"), 0.0);
  std::printf("[ info     ] killed live attempt: %zu frames (%.3f s), %zu events checkpointed\n",
              decoded.frames.size(), *a.duration_s, decoded.events.size());
  // The stored (and reported) events are the recording's, in order.
  EXPECT_EQ(shown["events"].size(), a.events.size());
  ASSERT_GE(decoded.events.size(), 1u);
  EXPECT_EQ(decoded.events[0].kind, EventKind::kInputRejected);
  ASSERT_EQ(a.events.size(), decoded.events.size());
  for (std::size_t i = 0; i < a.events.size(); ++i) {
    EXPECT_EQ(a.events[i].kind, event_kind_name(decoded.events[i].kind)) << i;
    EXPECT_EQ(a.events[i].t_s, decoded.events[i].t_s) << i;
  }
  EXPECT_FALSE(a.score.has_value());
  EXPECT_FALSE(a.passed.has_value());

  // Re-scored: the same metrics from the recording; still aborted, unscored, not passed.
  const std::string out = run_program(std::string(ACDR_EXE) + " rescore --db '" + db_path + "'");
  EXPECT_NE(out.find("aborted, not scored"), std::string::npos) << out;
  EXPECT_NE(out.find("metrics identical"), std::string::npos) << out;
  EXPECT_NE(out.find("1 attempt(s) re-scored, 0 changed"), std::string::npos) << out;
  Database db = test::open_or_fail(db_path);
  const AttemptRecord after = *load_attempt(db, a.id).value();
  EXPECT_EQ(after.status, AttemptStatus::kAborted);
  EXPECT_FALSE(after.score.has_value());
  EXPECT_FALSE(after.passed.has_value());
  EXPECT_EQ(after.metrics.values, a.metrics.values);
}

TEST(AcdrRunRecord, RescoringACompletedAttemptReproducesItsMetricsExactly) {
  test::TempDir dir;
  const std::string db_path = dir.file("record.sqlite");
  const std::string scene_path = write_scene(dir);
  const std::string trajectory = std::string(ACDR_SOURCE_DIR) + "/tests/ui/data/short_scoop.csv";
  run_program(std::string(ACDR_EXE) + " run '" + scene_path + "' --input 'replay:" + trajectory +
              "' --headless --db '" + db_path + "' --checkpoint-every 0.5 --json > /dev/null");
  {
    Database db = test::open_or_fail(db_path);
    auto attempts = list_attempts(db, {}, AttemptDetail{true, true, true});
    ASSERT_TRUE(attempts.ok()) << attempts.error().message;
    ASSERT_EQ(attempts->size(), 1u);
    const AttemptRecord& a = attempts->front();
    ASSERT_EQ(a.status, AttemptStatus::kCompleted);
    ASSERT_TRUE(a.recording.has_value());
    EXPECT_TRUE(a.recording->complete);  // the whole recording replaced the checkpoints
    EXPECT_EQ(a.recording->format, kRecordingFormat);
    std::string error;
    const auto decoded = decode_recording(a.recording->bytes, &error);
    ASSERT_TRUE(decoded) << error;
    EXPECT_EQ(a.metrics.values, compute_metrics(*decoded).values);
    DbResult<Statement> chunks = db.prepare("SELECT count(*) FROM recording_chunks");
    ASSERT_TRUE(chunks.ok());
    ASSERT_TRUE(chunks->step().value());
    EXPECT_EQ(chunks->column_int64(0), 0);
  }
  const std::string out = run_program(std::string(ACDR_EXE) + " rescore --db '" + db_path + "'");
  EXPECT_NE(out.find("metrics identical"), std::string::npos) << out;
  EXPECT_NE(out.find("1 attempt(s) re-scored, 0 changed"), std::string::npos) << out;
}

// `acdr ARGS` with stdout and stderr kept: its exit code and both texts.
struct Ran {
  int code = -1;
  std::string out, err;
};
Ran run_acdr(const test::TempDir& dir, const std::string& args,
             const std::string& environment = "") {
  const std::string out = dir.file("stdout.txt"), err = dir.file("stderr.txt");
  const int status = std::system(
      (environment + ACDR_EXE + " " + args + " >'" + out + "' 2>'" + err + "'").c_str());
  Ran r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void raw_exec(const std::string& path, const char* sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(db);
}

// Another program's SQLite file given as --db is refused by every command before anything
// writes to it: byte for byte unchanged, no WAL file, and the error says it was not changed.
// An empty file is not turned into a record by a command that only reads; `acdr run` may.
TEST(AcdrRunRecord, EveryCommandRefusesAForeignFileWithoutChangingIt) {
  test::TempDir dir;
  const std::string scene = write_scene(dir);
  const std::string trajectory = std::string(ACDR_SOURCE_DIR) + "/tests/ui/data/short_scoop.csv";
  const std::string tables = dir.file("notes.db");
  raw_exec(tables, "CREATE TABLE notes (x); INSERT INTO notes VALUES (1)");
  const std::string stamped = dir.file("stamped.db");
  raw_exec(stamped, "PRAGMA application_id = 1234; CREATE TABLE t (x)");
  const std::string empty = dir.file("empty.db");
  std::ofstream(empty).close();
  for (const std::string& db : {tables, stamped, empty}) {
    const std::string before = file_bytes(db);
    const std::vector<std::string> commands = {
        "report --db '" + db + "'",
        "rescore --db '" + db + "'",
        "rescore --dry-run --db '" + db + "'",
        "dashboard --db '" + db + "' --screenshot '" + dir.file("d.png") + "'",
        "run '" + scene + "' --headless --input 'replay:" + trajectory + "' --db '" + db + "'",
    };
    for (const std::string& command : commands) {
      if (db == empty && command.rfind("run ", 0) == 0) continue;  // below
      const Ran r = run_acdr(dir, command);
      EXPECT_EQ(r.code, 2) << command;  // every command: a refused record is bad input
      EXPECT_NE(r.err.find(db), std::string::npos) << command << "\n" << r.err;
      EXPECT_NE(r.err.find("not changed"), std::string::npos) << command << "\n" << r.err;
      EXPECT_EQ(file_bytes(db), before) << command;
      EXPECT_FALSE(std::filesystem::exists(db + "-wal")) << command;
      EXPECT_FALSE(std::filesystem::exists(dir.file("d.png"))) << command;
    }
  }
  EXPECT_EQ(std::filesystem::file_size(empty), 0u);
  // A run on an empty file starts a record there.
  const Ran started = run_acdr(dir, "run '" + scene + "' --headless --input 'replay:" +
                                        trajectory + "' --db '" + empty + "'");
  EXPECT_EQ(started.code, 0) << started.err;
  EXPECT_EQ(run_acdr(dir, "report --db '" + empty + "'").code, 0);
}

// Another program holds the record's write lock from before the attempt ends until after
// `acdr run` gave up: the run shows its result, keeps it in a side file next to the database
// and exits 5 ("record not written"), not 2. The next start (`acdr report`) stores it, says
// so, and the attempt is completed with all its seconds, its score and its recording.
TEST(AcdrRunRecord, AFinishedAttemptWhoseRecordIsLockedIsKeptAndStoredAtTheNextStart) {
  test::TempDir dir;
  const std::string db_path = dir.file("record.sqlite");
  const std::string trajectory = dir.file("long.csv");
  write_long_trajectory(std::string(ACDR_SOURCE_DIR) + "/tests/ui/data/short_scoop.csv",
                        trajectory, 3);  // 9 s
  const std::string scene_path = write_scene(dir);
  const std::string out_path = dir.file("run.json"), err_path = dir.file("run.err");

  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    if (!freopen(out_path.c_str(), "w", stdout) || !freopen(err_path.c_str(), "w", stderr))
      _exit(120);
    execl(ACDR_EXE, ACDR_EXE, "run", scene_path.c_str(), "--input",
          ("replay:" + trajectory).c_str(), "--headless", "--db", db_path.c_str(),
          "--checkpoint-every", "0", "--store-wait", "1", "--json", "--trainee", "t-lock",
          static_cast<char*>(nullptr));
    _exit(127);
  }
  // Once the attempt is begun (its row committed), take the write lock and keep it.
  sqlite3* locker = nullptr;
  bool locked = false;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  int status = 0;
  bool exited = false;
  while (!locked && std::chrono::steady_clock::now() < give_up) {
    if (waitpid(child, &status, WNOHANG) == child) {
      exited = true;
      break;
    }
    if (std::filesystem::exists(db_path)) {
      sqlite3* probe = nullptr;
      int attempts = 0;
      if (sqlite3_open_v2(db_path.c_str(), &probe, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
        sqlite3_stmt* s = nullptr;
        if (sqlite3_prepare_v2(probe, "SELECT count(*) FROM attempts", -1, &s, nullptr) ==
                SQLITE_OK &&
            sqlite3_step(s) == SQLITE_ROW)
          attempts = sqlite3_column_int(s, 0);
        sqlite3_finalize(s);
      }
      sqlite3_close(probe);
      if (attempts == 1) {
        ASSERT_EQ(sqlite3_open(db_path.c_str(), &locker), SQLITE_OK);
        sqlite3_busy_timeout(locker, 5000);
        locked = sqlite3_exec(locker, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr) == SQLITE_OK;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_FALSE(exited) << "acdr run ended before the lock was taken:\n" << read_text(err_path);
  ASSERT_TRUE(locked);
  ASSERT_EQ(waitpid(child, &status, 0), child);
  sqlite3_exec(locker, "ROLLBACK", nullptr, nullptr, nullptr);
  sqlite3_close(locker);

  const std::string err = read_text(err_path);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 5) << err;
  EXPECT_NE(err.find("could not be written"), std::string::npos) << err;
  EXPECT_NE(err.find("database is locked"), std::string::npos) << err;
  const nlohmann::json shown = nlohmann::json::parse(read_text(out_path));
  EXPECT_EQ(shown["stored_as"], "not written");
  const std::string side_file = shown["unsaved_file"].get<std::string>();
  EXPECT_EQ(side_file, db_path + ".attempt-" + std::to_string(shown["attempt_id"].get<int>()) +
                           ".unsaved");
  EXPECT_TRUE(std::filesystem::exists(side_file));
  const double duration = shown["duration_s"].get<double>();
  EXPECT_GT(duration, 8.5);

  // The next start stores it and says so.
  const Ran report = run_acdr(dir, "report --db '" + db_path + "' --format json");
  ASSERT_EQ(report.code, 0) << report.err;
  EXPECT_NE(report.err.find("now stored"), std::string::npos) << report.err;
  EXPECT_FALSE(std::filesystem::exists(side_file));
  const nlohmann::json stored = nlohmann::json::parse(report.out);
  ASSERT_EQ(stored["attempts"].size(), 1u);
  const nlohmann::json& a = stored["attempts"][0];
  EXPECT_EQ(a["status"], "completed");
  EXPECT_EQ(a["duration_s"].get<double>(), duration);
  EXPECT_EQ(a["score"].get<double>(), shown["score"].get<double>());
  EXPECT_EQ(a["passed"], shown["passed"]);
  Database db = test::open_or_fail(db_path);
  EXPECT_EQ(test::integrity_check(db), "ok");
  const AttemptRecord record = test::the_only_attempt(db);
  ASSERT_TRUE(record.recording.has_value());
  EXPECT_TRUE(record.recording->complete);
  std::string error;
  const auto decoded = decode_recording(record.recording->bytes, &error);
  ASSERT_TRUE(decoded) << error;
  EXPECT_NEAR(decoded->frames.back().t_s, duration, 1e-9);
  EXPECT_EQ(record.metrics.values, compute_metrics(*decoded).values);
}

// A small tmpfs mounted for one test (needs the privilege to mount; the test is skipped
// without it), unmounted at the end.
class TinyFileSystem {
 public:
  TinyFileSystem(const std::string& where, const char* size) : where_(where) {
    std::filesystem::create_directories(where);
    mounted_ = mount("acdr-test", where.c_str(), "tmpfs", 0, (std::string("size=") + size).c_str()) == 0;
  }
  ~TinyFileSystem() {
    if (mounted_) umount2(where_.c_str(), MNT_DETACH);
  }
  bool mounted() const { return mounted_; }
  // Fills it up to `leave` bytes free.
  void fill(std::size_t leave) {
    struct statvfs st {};
    if (statvfs(where_.c_str(), &st) != 0) return;
    const std::size_t free_bytes = static_cast<std::size_t>(st.f_bavail) * st.f_frsize;
    std::ofstream filler(where_ + "/filler", std::ios::binary);
    const std::string block(4096, '\0');
    for (std::size_t n = 0; n + leave + block.size() <= free_bytes; n += block.size()) filler << block;
  }
  void empty() { std::filesystem::remove(where_ + "/filler"); }

 private:
  std::string where_;
  bool mounted_ = false;
};

// The disk of the record fills up during an attempt: the run exits 5, the result goes to the
// fallback directory (the full disk refuses the side file next to the database too), and once
// space is back the next start stores it: the attempt is completed with all its seconds.
TEST(AcdrRunRecord, AFullDiskKeepsTheResultInTheFallbackDirectory) {
  test::TempDir dir, state;
  TinyFileSystem disk(dir.file("disk"), "4m");
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (needs CAP_SYS_ADMIN)";
  const std::string db_path = dir.file("disk/record.sqlite");
  const std::string trajectory = dir.file("long.csv");
  write_long_trajectory(std::string(ACDR_SOURCE_DIR) + "/tests/ui/data/short_scoop.csv",
                        trajectory, 3);  // 9 s
  const std::string scene_path = write_scene(dir);
  const std::string out_path = dir.file("run.json"), err_path = dir.file("run.err");
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    setenv("XDG_STATE_HOME", state.path().c_str(), 1);
    if (!freopen(out_path.c_str(), "w", stdout) || !freopen(err_path.c_str(), "w", stderr))
      _exit(120);
    execl(ACDR_EXE, ACDR_EXE, "run", scene_path.c_str(), "--input",
          ("replay:" + trajectory).c_str(), "--headless", "--db", db_path.c_str(),
          "--checkpoint-every", "2", "--store-wait", "1", "--json", static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  const bool exited = exited_before_chunks(db_path, child, 1, &status);
  ASSERT_FALSE(exited) << read_text(err_path);
  disk.fill(200 * 1024);  // far less than the recording needs
  ASSERT_EQ(waitpid(child, &status, 0), child);
  const std::string err = read_text(err_path);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 5) << err;
  EXPECT_NE(err.find("full"), std::string::npos) << err;
  const nlohmann::json shown = nlohmann::json::parse(read_text(out_path));
  const std::string side_file = shown["unsaved_file"].get<std::string>();
  EXPECT_EQ(std::filesystem::path(side_file).parent_path(), state.path() / "acdr" / "unsaved");
  EXPECT_TRUE(std::filesystem::exists(side_file));

  // Space is back: the next start (with the same fallback directory) stores it.
  disk.empty();
  const Ran report = run_acdr(dir, "report --db '" + db_path + "' --format json",
                              "XDG_STATE_HOME='" + state.path().string() + "' ");
  ASSERT_EQ(report.code, 0) << report.err;
  EXPECT_NE(report.err.find("now stored"), std::string::npos) << report.err;
  EXPECT_FALSE(std::filesystem::exists(side_file));
  const nlohmann::json stored = nlohmann::json::parse(report.out);
  ASSERT_EQ(stored["attempts"].size(), 1u);
  EXPECT_EQ(stored["attempts"][0]["status"], "completed");
  EXPECT_EQ(stored["attempts"][0]["duration_s"].get<double>(), shown["duration_s"].get<double>());
  EXPECT_EQ(stored["attempts"][0]["score"].get<double>(), shown["score"].get<double>());
}

}  // namespace
}  // namespace acdr
