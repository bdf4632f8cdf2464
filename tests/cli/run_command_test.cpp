// Tests of cli/run_command.cpp driven through the UDP haptic bridge on loopback by the
// virtual device (engine/devices/virtual_bridge.hpp), as `acdr run --input udp:PORT` with `acdr
// device-sim`: the attempt completes and reports its haptics, its row exists before the first
// packet, device faults are recorded, and a silent or absent device ends the attempt,
// and another local sender is ignored.
//
// The scene is the test box without material (tests/ui/data/empty_box.json), so that the
// physics step is far below 1 ms and the 1 kHz loop is reachable on a loaded machine.
#include "cli/run_command.hpp"

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <future>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "db/attempt_store.hpp"
#include "engine/devices/udp_socket.hpp"
#include "engine/devices/virtual_bridge.hpp"
#include "tests/db/db_test_support.hpp"

namespace acdr {
namespace {

using namespace std::chrono_literals;

const std::string kData = std::string(ACDR_SOURCE_DIR) + "/tests/ui/data/";

// A UDP port free right now (bound and released).
int free_port() {
  std::string error;
  auto s = UdpSocket::bind("127.0.0.1", 0, &error);
  EXPECT_TRUE(s) << error;
  return s ? s->local_port() : 0;
}

struct UdpRun {
  int code = -1;
  nlohmann::json result;
  std::string err;
  VirtualBridgeResult bridge;
};

// `acdr run empty_box.json --headless --input udp:PORT --json` with the virtual device playing
// the short scoop; `bridge_delay` lets the run wait for the bridge first.
UdpRun run_with_bridge(const std::string& db, VirtualBridgeOptions bridge,
                       double device_timeout_s = 5.0,
                       std::chrono::milliseconds bridge_delay = 0ms,
                       const std::string& scene = "empty_box.json",
                       double checkpoint_every_s = 5.0, int chosen_port = 0) {
  UdpRun r;
  const int port = chosen_port > 0 ? chosen_port : free_port();
  RunOptions options;
  options.scenario = kData + scene;
  options.checkpoint_every_s = checkpoint_every_s;
  options.input = "udp:" + std::to_string(port);
  options.db = db;
  options.json = true;
  options.headless = true;
  options.device_timeout_s = device_timeout_s;
  auto trajectory = Trajectory::load_csv(kData + "short_scoop.csv", &r.err);
  EXPECT_TRUE(trajectory) << r.err;
  bridge.port = port;
  bridge.connect_timeout_s = 10.0;
  auto bridge_done = std::async(std::launch::async, [&] {
    std::this_thread::sleep_for(bridge_delay);
    return VirtualBridge(*trajectory, bridge).run();
  });
  std::ostringstream out, err;
  r.code = run_run(options, out, err);
  r.err = err.str();
  r.bridge = bridge_done.get();
  if (!out.str().empty()) r.result = nlohmann::json::parse(out.str());
  return r;
}

std::vector<std::string> event_kinds(const nlohmann::json& result) {
  std::vector<std::string> kinds;
  for (const auto& e : result["events"]) kinds.push_back(e["kind"]);
  return kinds;
}
bool has(const std::vector<std::string>& v, const std::string& x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

TEST(RunCommandUdp, DeviceSimDrivesTheAttemptToItsEndAndHapticsAreReported) {
  test::TempDir dir;
  const UdpRun r = run_with_bridge(dir.file("r.sqlite"), {});
  ASSERT_EQ(r.code, 0) << r.err;
  const auto& j = r.result;
  EXPECT_EQ(j["end"], "input ended");
  EXPECT_EQ(j["stored_as"], "completed");
  // The 3 s trajectory at the scenario's 1 ms step.
  EXPECT_NEAR(j["duration_s"].get<double>(), 3.0, 0.1);
  ASSERT_TRUE(j.contains("haptics"));
  const auto& h = j["haptics"];
  // Acceptance is >= 950 Hz; the mean rate of the absolute schedule stays at 1 kHz unless the
  // loop had to resync, which a heavily loaded test machine can force once or twice.
  EXPECT_GE(h["rate_hz"].get<double>(), 900.0);
  EXPECT_GT(h["period_p99_ms"].get<double>(), 0.0);
  EXPECT_EQ(h["packets_lost"], 0);
  EXPECT_LE(h["max_force_sent_N"].get<double>(), 3.3 + 1e-9);
  EXPECT_GT(h["max_force_sent_N"].get<double>(), 0.0);
  // Clamping is timing-dependent on a loaded machine (a late tick sees a burst of motion), so
  // only its bookkeeping is checked: the count matches the recorded events.
  int clamped = 0;
  for (const auto& e : j["events"]) clamped += e["kind"] == "force_clamped";
  EXPECT_EQ(h["force_clamped_events"], clamped);
  // The device got its forces and the attempt-over.
  EXPECT_TRUE(r.bridge.attempt_over);
  EXPECT_EQ(r.bridge.attempt_over_reason, bridge::EndReason::kInputEnded);
  EXPECT_GT(r.bridge.forces_received, 2500);
  EXPECT_LE(r.bridge.max_force_N, 3.3 + 1e-9);
  // Stored, with its recording and the device it came from.
  Database db = test::open_or_fail(dir.file("r.sqlite"));
  auto stored = load_attempt(db, j["attempt_id"].get<std::int64_t>());
  ASSERT_TRUE(stored && stored.value());
  EXPECT_EQ(stored.value()->status, AttemptStatus::kCompleted);
  EXPECT_EQ(stored.value()->input_device.rfind("udp:", 0), 0u);
  EXPECT_TRUE(stored.value()->recording.has_value());
}

TEST(RunCommandUdp, TheAttemptRowExistsBeforeTheFirstPacket) {
  test::TempDir dir;
  const std::string path = dir.file("r.sqlite");
  std::promise<bool> seen_running;
  // A watcher reads the record while the run waits for the (late) bridge.
  std::thread watcher([&] {
    bool seen = false;
    for (int i = 0; i < 200 && !seen; ++i) {
      std::this_thread::sleep_for(10ms);
      auto db = Database::open(path, OpenOptions{.create = false});
      if (!db) continue;
      auto attempts = list_attempts(db.value());
      if (attempts && !attempts->empty() && attempts->front().status == AttemptStatus::kRunning)
        seen = true;
    }
    seen_running.set_value(seen);
  });
  const UdpRun r = run_with_bridge(path, {}, 5.0, 800ms);
  watcher.join();
  EXPECT_TRUE(seen_running.get_future().get());
  EXPECT_EQ(r.code, 0) << r.err;
}

TEST(RunCommandUdp, DeviceFaultsAreRecordedAsEvents) {
  test::TempDir dir;
  VirtualBridgeOptions faults;
  faults.nan_at_s = 0.5;
  faults.jump_at_s = 1.0;
  faults.silence_at_s = 2.0;
  faults.silence_for_s = 0.2;  // beyond the 50 ms silence limit, short of the disconnect
  faults.drop_every = 100;
  const UdpRun r = run_with_bridge(dir.file("r.sqlite"), faults);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto kinds = event_kinds(r.result);
  EXPECT_TRUE(has(kinds, "input_rejected"));  // the NaN and the jump
  EXPECT_TRUE(has(kinds, "input_lost"));      // the silence
  int rejected = 0;
  for (const auto& e : r.result["events"]) {
    if (e["kind"] != "input_rejected") continue;
    ++rejected;
  }
  EXPECT_GE(rejected, 2);
  const auto& h = r.result["haptics"];
  EXPECT_EQ(h["packets_lost"].get<std::int64_t>(), r.bridge.poses_dropped);
  EXPECT_GE(h["input_lost_events"].get<int>(), 1);
  EXPECT_LE(h["max_force_sent_N"].get<double>(), 3.3 + 1e-9);
}

// A second local program that floods the attempt's port mid-attempt with poses of higher
// sequence numbers (far from the bridge's, so a take-over would show as a pose jump) and says
// hello: it gets nothing back, the bridge keeps every force and its attempt, and the run
// reports the ignored datagrams.
TEST(RunCommandUdp, AnIntruderMidAttemptGetsNoForceAndChangesNothing) {
  test::TempDir dir;
  std::string error;
  auto intruder = UdpSocket::bind("127.0.0.1", 0, &error);
  ASSERT_TRUE(intruder) << error;
  std::atomic<bool> stop{false};
  std::atomic<int> port{0};
  std::atomic<long> intruder_sent{0}, intruder_received{0};
  std::thread flood([&] {
    std::this_thread::sleep_for(1500ms);  // mid-attempt
    std::array<std::uint8_t, bridge::kMaxMessageSize + 1> in;
    for (std::uint32_t k = 0; !stop.load(); ++k) {
      bridge::Message m;
      m.type = k % 50 == 0 ? bridge::MessageType::kHello : bridge::MessageType::kPose;
      m.sequence = 1000000 + k;
      m.nonce = 77;
      m.pose.position = Vec3(0.05, 0.05, 0.2);
      std::array<std::uint8_t, bridge::kMaxMessageSize> out;
      const std::size_t n = bridge::encode(m, out);
      if (intruder->send_to(make_endpoint("127.0.0.1", port.load()),
                            std::span<const std::uint8_t>(out.data(), n)))
        ++intruder_sent;
      while (intruder->receive(in, nullptr) > 0) ++intruder_received;
      std::this_thread::sleep_for(1ms);
    }
  });
  const int chosen = free_port();
  port = chosen;
  const UdpRun r = run_with_bridge(dir.file("r.sqlite"), {}, 5.0, 0ms, "empty_box.json", 5.0,
                                   chosen);
  stop = true;
  flood.join();
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GT(intruder_sent.load(), 500);
  EXPECT_EQ(intruder_received.load(), 0);
  const auto& link = r.result["haptics"]["link"];
  EXPECT_GT(link["packets_foreign"].get<std::int64_t>(), 500);
  EXPECT_EQ(r.result["end"], "input ended");
  EXPECT_NEAR(r.result["duration_s"].get<double>(), 3.0, 0.1);
  EXPECT_EQ(r.result["haptics"]["packets_lost"], 0);
  EXPECT_EQ(link["packets_late"], 0);
  EXPECT_FALSE(has(event_kinds(r.result), "input_rejected"));  // no jump to the intruder's pose
  EXPECT_TRUE(r.bridge.attempt_over);
  EXPECT_GT(r.bridge.forces_received, 2500);
  EXPECT_EQ(r.bridge.forces_lost, 0);
}

TEST(RunCommandUdp, ASilentDeviceEndsTheAttemptAsDisconnected) {
  test::TempDir dir;
  VirtualBridgeOptions faults;
  faults.silence_at_s = 0.5;
  faults.silence_for_s = 10.0;  // never comes back
  const auto start = std::chrono::steady_clock::now();
  const UdpRun r = run_with_bridge(dir.file("r.sqlite"), faults, /*device_timeout_s=*/0.3);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.result["end"], "device disconnected");
  const auto kinds = event_kinds(r.result);
  EXPECT_TRUE(has(kinds, "input_lost"));
  EXPECT_TRUE(has(kinds, "device_disconnected"));
  // The disconnect is declared on the wall clock: 0.3 s after the last pose, sent at 0.5 s,
  // and long before the device would speak again (10.5 s). The simulated duration cannot
  // exceed that (the physics never runs ahead of the clock), but on a loaded host it may fall
  // behind, so only its upper bound is fixed.
  EXPECT_GE(wall_s, 0.75);
  EXPECT_LT(wall_s, 5.0);
  EXPECT_GT(r.result["duration_s"].get<double>(), 0.0);
  EXPECT_LE(r.result["duration_s"].get<double>(), 0.95);
  EXPECT_TRUE(r.bridge.attempt_over);
  EXPECT_EQ(r.bridge.attempt_over_reason, bridge::EndReason::kDisconnected);
}

TEST(RunCommandUdp, NoBridgeAbortsTheAttemptAndSaysWhy) {
  test::TempDir dir;
  RunOptions options;
  options.scenario = kData + "empty_box.json";
  options.input = "udp:" + std::to_string(free_port());
  options.db = dir.file("r.sqlite");
  options.headless = true;
  options.device_timeout_s = 0.2;
  std::ostringstream out, err;
  EXPECT_EQ(run_run(options, out, err), 2);
  EXPECT_NE(err.str().find("no packet from the device bridge"), std::string::npos) << err.str();
  Database db = test::open_or_fail(options.db);
  auto attempts = list_attempts(db);
  ASSERT_TRUE(attempts);
  ASSERT_EQ(attempts->size(), 1u);
  EXPECT_EQ(attempts->front().status, AttemptStatus::kAborted);
}

TEST(RunCommandUdp, BadInputSpellingsAreUsageErrors) {
  for (const char* spec : {"udp:", "udp:abc", "udp:70000", "joystick"}) {
    RunOptions options;
    options.scenario = kData + "empty_box.json";
    options.input = spec;
    options.headless = true;
    options.db = "/nonexistent/never-created.sqlite";
    std::ostringstream out, err;
    EXPECT_EQ(run_run(options, out, err), 2) << spec;
    EXPECT_FALSE(err.str().empty()) << spec;
  }
}

}  // namespace
}  // namespace acdr

// records: checkpoints of a live attempt
namespace acdr {
namespace {

// A live attempt over the bridge checkpoints on a writer thread of its own, and is then stored
// whole. The physics loop's step times with checkpoints on and off are printed (a measurement:
// timing on a shared machine is not asserted). The small box has material, so the physics
// step is real work.
TEST(RunCommandUdp, ALiveAttemptCheckpointsBesideItsPhysicsLoop) {
  for (double every : {0.0, 0.25}) {
    test::TempDir dir;
    const UdpRun r =
        run_with_bridge(dir.file("r.sqlite"), {}, 5.0, std::chrono::milliseconds(0),
                        "small_box.json", every);
    ASSERT_EQ(r.code, 0) << r.err;
    const auto& j = r.result;
    EXPECT_EQ(j["stored_as"], "completed");
    const auto& p = j["haptics"]["physics"];
    std::printf("[ measure  ] live udp, checkpoints every %.2f s: physics %.0f Hz, step mean "
                "%.3f ms, p99 %.3f ms, max %.3f ms, period max %.3f ms, %lld overruns\n",
                every, p["rate_hz"].get<double>(), p["step_mean_ms"].get<double>(),
                p["step_p99_ms"].get<double>(), p["step_max_ms"].get<double>(),
                p["period_max_ms"].get<double>(),
                static_cast<long long>(p["overruns"].get<std::int64_t>()));
    Database db = test::open_or_fail(dir.file("r.sqlite"));
    auto stored = load_attempt(db, j["attempt_id"].get<std::int64_t>());
    ASSERT_TRUE(stored && stored.value());
    ASSERT_TRUE(stored.value()->recording.has_value());
    EXPECT_TRUE(stored.value()->recording->complete);  // the whole recording replaced them
    if (every == 0.0) {
      EXPECT_FALSE(j.contains("checkpoints"));
      continue;
    }
    ASSERT_TRUE(j.contains("checkpoints")) << j.dump(2);
    const auto& c = j["checkpoints"];
    std::printf("[ measure  ] writer thread: %lld checkpoints, %lld deferred, largest %lld "
                "frames, write mean %.1f ms, max %.1f ms; physics-side hand-over max %.3f ms\n",
                static_cast<long long>(c["saved"].get<std::int64_t>()),
                static_cast<long long>(c["deferred"].get<std::int64_t>()),
                static_cast<long long>(c["largest_frames"].get<std::int64_t>()),
                c["write_mean_ms"].get<double>(), c["write_max_ms"].get<double>(),
                c["handover_max_ms"].get<double>());
    // Due every 0.25 s of simulated time (less than the bridge's 3 s when the physics loop
    // falls behind on a loaded machine), except at the very end: each one saved or deferred.
    const int due = static_cast<int>(j["duration_s"].get<double>() / 0.25 + 1e-6);
    EXPECT_GE(c["saved"].get<int>(), 3);
    EXPECT_EQ(c["failed"], 0);
    EXPECT_GE(c["saved"].get<int>() + c["deferred"].get<int>(), due - 1);
    EXPECT_LE(c["saved"].get<int>() + c["deferred"].get<int>(), due);
    EXPECT_TRUE(c["writer_background_priority"].get<bool>());
    EXPECT_GT(c["write_max_ms"].get<double>(), 0.0);
    DbResult<Statement> chunks = db.prepare("SELECT count(*) FROM recording_chunks");
    ASSERT_TRUE(chunks.ok());
    ASSERT_TRUE(chunks->step().value());
    EXPECT_EQ(chunks->column_int64(0), 0);
  }
}

}  // namespace
}  // namespace acdr
