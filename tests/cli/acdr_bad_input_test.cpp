// End to end with the acdr program, each way a file used to crash or hang it reproduced as it
// was found: a scenario that validated but asked for more memory than a run has (a day-long time
// limit, a 1 µs step, a 0.05 mm distance grid with a 20 mm margin, a million-particle block), a
// denormal step, a mesh or a trajectory that is /dev/zero, /dev/urandom or a FIFO, hexadecimal
// floats and a negative start time in a trajectory, and a run that runs out of memory. Each now
// ends with a clear error (or runs, for a scaled quaternion), by exit code, never by a signal,
// within 20 s, under a 4 GB address-space limit.
#include <sqlite3.h>
#include <sys/stat.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/cli/acdr_process.hpp"

namespace acdr {
namespace {

namespace fs = std::filesystem;
using test::ProcessResult;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string source(const std::string& relative) { return std::string(ACDR_SOURCE_DIR) + "/" + relative; }

std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("not in text: " + from);
  return text.replace(at, from.size(), to);
}

class AcdrBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("acdr_bad_input_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // The box module's demonstration, cut to its first 0.1 s.
    std::ifstream in(source("content/demonstrations/01_box_warmup/expert_1.csv"));
    std::ofstream out(path("short.csv"));
    for (std::string line; std::getline(in, line);) {
      if (!line.empty() && std::isdigit(static_cast<unsigned char>(line[0])) && std::stod(line) > 0.1) break;
      out << line << "\n";
    }
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
    return path(name);
  }

  /// `acdr ARGS...` under the 4 GB limit; checks it ended by itself within 20 s, without a signal.
  ProcessResult acdr(std::vector<std::string> args, std::size_t address_space = test::kFourGigabytes) const {
    args.insert(args.begin(), ACDR_EXE);
    const ProcessResult r = test::run_process(args, address_space, 20.0);
    EXPECT_FALSE(r.timed_out) << r.output;
    EXPECT_EQ(r.signal, 0) << r.output;
    EXPECT_LT(r.seconds, 20.0);
    return r;
  }
  ProcessResult validate(const std::string& scenario) const { return acdr({"validate", scenario}); }
  ProcessResult run(const std::string& scenario, const std::string& trajectory) const {
    return acdr({"run", scenario, "--input", "replay:" + trajectory, "--headless", "--db", path("record.db")});
  }

  /// A scenario that validates before the budget existed: both commands refuse it with `message`.
  void expect_refused(const std::string& scenario, const std::string& message) const {
    const ProcessResult v = validate(scenario);
    EXPECT_EQ(v.exit_code, 1) << v.output;
    EXPECT_NE(v.output.find(message), std::string::npos) << v.output;
    const ProcessResult r = run(scenario, path("short.csv"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << r.output;
  }

  fs::path dir_;
};

/// An address-space limit that holds the program, its record and a small scene, but not the
/// scene of RunningOutOfMemoryAbortsTheAttemptWithAMessage.
constexpr std::size_t kOutOfMemoryLimit = std::size_t{350} << 20;

std::string box() { return read_text(source("scenarios/modules/01_box_warmup.json")); }

TEST_F(AcdrBadInput, ADayLongTimeLimitIsRefusedBeforeAnythingIsBuilt) {
  expect_refused(write("day.json", replace_once(box(), "\"time_limit_s\": 60", "\"time_limit_s\": 86400")),
                 "/time_limit_s: recording too long (got 86400000 frames: 86400 s at a 1 ms step, expected at most 1000000");
}

TEST_F(AcdrBadInput, StepsBelowTheFloorAndDenormalsAreOutOfRange) {
  for (const char* dt : {"0.001", "1e-6", "1e-9", "1e-320"}) {
    SCOPED_TRACE(dt);
    expect_refused(write("dt.json", replace_once(box(), "\"dt_ms\": 1,", std::string("\"dt_ms\": ") + dt + ",")),
                   "/world/solver/dt_ms: out of range (got ");
    const ProcessResult v = validate(path("dt.json"));
    EXPECT_NE(v.output.find(">= 0.1 ms and <= 10 ms)"), std::string::npos) << v.output;
  }
}

TEST_F(AcdrBadInput, AFineWideDistanceGridIsRefused) {
  const std::string text = replace_once(read_text(source("scenarios/modules/02_c4c5_healthy.json")),
                                        "\"sdf\": { \"spacing_mm\": 0.25 }",
                                        "\"sdf\": { \"spacing_mm\": 0.05, \"margin_mm\": 20 }");
  expect_refused(write("grid.json", text), "/world/anatomy/sdf/spacing_mm: distance grids too large (got about ");
}

TEST_F(AcdrBadInput, AMillionParticleBlockIsRefused) {
  std::string text = replace_once(box(), "\"spacing_mm\": 2", "\"spacing_mm\": 0.1");
  text = replace_once(text, "{ \"min_mm\": [-15, -10, 0], \"max_mm\": [15, 10, 8]",
                      "{ \"min_mm\": [-5, -5, 0], \"max_mm\": [4.95, 4.95, 9.95]");
  expect_refused(write("million.json", text),
                 "/world/nucleus/blocks: too many particles (got about 1000000 at spacing 0.1 mm, expected at most 300000");
}

TEST_F(AcdrBadInput, MeshesThatAreDevicesOrFifosAreRefusedAtOnce) {
  fs::copy_file(source("tests/scenarios/data/bone_c5.stl"), dir_ / "bone_c5.stl");
  fs::create_symlink("/dev/zero", dir_ / "zero.stl");
  fs::create_symlink("/dev/urandom", dir_ / "random.obj");
  ASSERT_EQ(::mkfifo(path("pipe.stl").c_str(), 0600), 0);
  const std::string complete = read_text(source("tests/scenarios/data/complete.json"));
  for (const char* name : {"zero.stl", "random.obj", "pipe.stl"}) {
    SCOPED_TRACE(name);
    const std::string scenario =
        write("meshes.json", replace_once(complete, "\"c4\": \"bone_c4.obj\"", std::string("\"c4\": \"") + name + "\""));
    const ProcessResult v = validate(scenario);
    EXPECT_EQ(v.exit_code, 1) << v.output;
    EXPECT_NE(v.output.find("/world/anatomy/meshes: " + path(name) + ": not a regular file (got a "), std::string::npos)
        << v.output;
  }
}

TEST_F(AcdrBadInput, TrajectoriesThatAreDevicesOrFifosAreRefusedAtOnce) {
  const std::string scenario = source("scenarios/modules/01_box_warmup.json");
  fs::create_symlink("/dev/urandom", dir_ / "random.csv");
  ASSERT_EQ(::mkfifo(path("pipe.csv").c_str(), 0600), 0);
  for (const std::string& file : {std::string("/dev/zero"), path("random.csv"), path("pipe.csv")}) {
    SCOPED_TRACE(file);
    const ProcessResult r = run(scenario, file);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(file + ": not a regular file (got a "), std::string::npos) << r.output;
  }
}

TEST_F(AcdrBadInput, TrajectoriesWithHexFloatsOrANegativeStartAreRefused) {
  const std::string scenario = source("scenarios/modules/01_box_warmup.json");
  const std::string header = "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";
  ProcessResult r = run(scenario, write("hex.csv", header + "0,0,0,0.11,1,0,0,0\n0x1p-3,0,0,0.11,1,0,0,0\n"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("hex.csv:3: field 1 is not a finite number (got '0x1p-3'"), std::string::npos) << r.output;
  r = run(scenario, write("negative.csv", header + "-1,0,0,0.11,1,0,0,0\n0.1,0,0,0.11,1,0,0,0\n"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("negative.csv:2: negative time (got -1, expected the first sample at t_s >= 0)"),
            std::string::npos) << r.output;
}

TEST_F(AcdrBadInput, ScaledQuaternionsAreTheSameRotation) {
  // The identity scaled by 1e300 and by 1e-200: read as the identity, so no pose is rejected.
  const std::string scenario = source("scenarios/modules/01_box_warmup.json");
  for (const char* w : {"1e300", "1e-200"}) {
    SCOPED_TRACE(w);
    const std::string header = "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";
    const std::string csv = write("scaled.csv", header + "0,0,0,0.11," + w + ",0,0,0\n0.1,0,0,0.11," + w + ",0,0,0\n");
    const ProcessResult r = acdr({"run", scenario, "--input", "replay:" + csv, "--headless", "--db", path("record.db"),
                                  "--json"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
    ASSERT_TRUE(j["events"].is_array()) << r.output;
    for (const nlohmann::json& e : j["events"]) EXPECT_NE(e["kind"], "input_rejected") << r.output;
  }
}

/// The status and abort reason of attempt `id` in the record at `db_path`.
std::pair<std::string, std::string> attempt_status(const std::string& db_path, int id) {
  sqlite3* db = nullptr;
  std::pair<std::string, std::string> out;
  if (sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT status, abort_reason FROM attempts WHERE id = ?", -1, &s, nullptr) == SQLITE_OK) {
      sqlite3_bind_int(s, 1, id);
      if (sqlite3_step(s) == SQLITE_ROW) {
        out.first = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
        out.second = reinterpret_cast<const char*>(sqlite3_column_text(s, 1));
      }
      sqlite3_finalize(s);
    }
  }
  sqlite3_close(db);
  return out;
}

TEST_F(AcdrBadInput, RunningOutOfMemoryAbortsTheAttemptWithAMessage) {
  // A valid scenario on a machine with less memory than it needs: the program, the record and
  // the scenario fit in the limit, the scene does not.
  std::string text = replace_once(box(), "\"spacing_mm\": 2", "\"spacing_mm\": 0.4");
  const std::string scenario = write("big.json", text);
  ASSERT_EQ(validate(scenario).exit_code, 0);
  const ProcessResult r = acdr({"run", scenario, "--input", "replay:" + path("short.csv"), "--headless", "--db",
                                path("record.db")},
                               kOutOfMemoryLimit);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("out of memory while building or running the scene"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(attempt 1 stored as aborted)"), std::string::npos) << r.output;
  const auto [status, reason] = attempt_status(path("record.db"), 1);
  EXPECT_EQ(status, "aborted");
  EXPECT_NE(reason.find("out of memory"), std::string::npos) << reason;
}

}  // namespace
}  // namespace acdr
