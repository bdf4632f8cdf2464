// How an attempt's result is shown: a readable summary for people, JSON for programs.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "app/attempt_session.hpp"

namespace acdr {

/// The `haptics` object of `acdr run --json`: rate_hz, period_p99_ms, packets_lost,
/// force_clamped_events, max_force_sent_N, and more (docs/haptic-bridge.md).
nlohmann::json haptics_json(const HapticsReport& haptics, const AttemptRun& run);

/// The `acdr run --json` object of a session that ran (`result.ran()`): scenario,
/// scenario_hash, duration_s, steps, metrics, score, passed, and more (docs/commands.md);
/// `png_path`: the picture of the final frame, when one was written.
nlohmann::json result_json(const SessionResult& result, const std::string& png_path);

/// A score summary for the terminal, of the same.
std::string result_summary(const SessionResult& result, const std::string& png_path);

}  // namespace acdr
