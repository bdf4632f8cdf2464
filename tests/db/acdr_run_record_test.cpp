// End to end (issue 6 acceptance) with the acdr program: `acdr run` killed by SIGKILL
// mid-attempt leaves an intact record, and the next start (`acdr report`) shows the attempt
// aborted with the recording and the metrics of its last checkpoint, which agree exactly; a
// completed attempt re-scored by `acdr rescore` reproduces its stored metrics exactly.
#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

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
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  int status = 0;
  bool exited = false;
  while (committed_chunks(db_path) < 3 && std::chrono::steady_clock::now() < deadline) {
    if (waitpid(child, &status, WNOHANG) == child) {
      exited = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
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
  {
    DbResult<Statement> s = db.prepare("PRAGMA integrity_check");
    ASSERT_TRUE(s.ok());
    ASSERT_TRUE(s->step().value());
    EXPECT_EQ(s->column_text(0), "ok");
  }
  auto attempts = list_attempts(db, {}, AttemptDetail{true, true, true});
  ASSERT_TRUE(attempts.ok()) << attempts.error().message;
  ASSERT_EQ(attempts->size(), 1u);
  const AttemptRecord& a = attempts->front();
  EXPECT_EQ(a.status, AttemptStatus::kAborted);
  ASSERT_TRUE(a.recording.has_value());
  EXPECT_FALSE(a.recording->complete);
  std::string error;
  const auto decoded = decode_recording(a.recording->bytes, &error);
  ASSERT_TRUE(decoded) << error;
  ASSERT_GE(decoded->frames.size(), 300u);  // at least three 0.1 s checkpoints at 1 kHz
  EXPECT_EQ(static_cast<std::int64_t>(decoded->frames.size()), a.recording->frame_count);
  EXPECT_EQ(a.metrics.values, compute_metrics(*decoded).values);
  EXPECT_EQ(a.duration_s, std::optional<double>(decoded->frames.back().t_s));
  EXPECT_GT(*a.metrics.find("tip_path_length_mm"), 0.0);
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

}  // namespace
}  // namespace acdr
