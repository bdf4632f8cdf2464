// How an attempt's result is shown: a readable summary for people, JSON for programs.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "app/attempt_runner.hpp"
#include "engine/devices/haptic_loop.hpp"
#include "engine/devices/udp_device.hpp"
#include "engine/world/world.hpp"
#include "scenarios/scenario_model.hpp"

namespace acdr {

/// How a live device drove the attempt: the haptic loop's achieved rate and the link's figures
/// (the UDP bridge's, when there was one).
struct HapticsReport {
  HapticLoopStats loop;     ///< the device loop (the only loop for a replay)
  bool decoupled = false;   ///< the physics had a loop of its own (a live device)
  HapticLoopStats physics;  ///< that loop, when decoupled
  std::int64_t device_ticks_clamped = 0;  ///< device-loop forces clamped to the maximum
  std::int64_t device_ticks_zeroed = 0;   ///< device-loop forces zeroed (stale/NaN/jump)
  bool has_link = false;
  UdpDeviceStats link;
};

/// The `haptics` object of `acdr run --json`: rate_hz, period_p99_ms, packets_lost,
/// force_clamped_events, max_force_sent_N, and more (docs/haptic-bridge.md).
nlohmann::json haptics_json(const HapticsReport& haptics, const AttemptRun& run);

struct ResultContext {
  const ScenarioModel& scenario;
  const AttemptRun& run;
  const World& world;
  std::int64_t attempt_id = 0;
  std::string db_path;
  std::string png_path;
  const HapticsReport* haptics = nullptr;  ///< set when a live device drove the attempt
  std::string stored_as = "completed";     ///< or "aborted" (the trainee left)
};

/// The `acdr run --json` object: scenario, scenario_hash, duration_s, steps, metrics, score,
/// passed, and more (docs/commands.md).
nlohmann::json result_json(const ResultContext& context);

/// A score summary for the terminal.
std::string result_summary(const ResultContext& context);

}  // namespace acdr
