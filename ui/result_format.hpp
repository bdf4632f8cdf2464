// How an attempt's result is shown: a readable summary for people, JSON for programs.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "engine/world.hpp"
#include "scenarios/scenario_model.hpp"
#include "ui/attempt_runner.hpp"

namespace acdr {

struct ResultContext {
  const ScenarioModel& scenario;
  const AttemptRun& run;
  const World& world;
  std::int64_t attempt_id = 0;
  std::string db_path;
  std::string png_path;
};

/// The `acdr run --json` object: scenario, scenario_hash, duration_s, steps, metrics, score,
/// passed, and more (docs/commands.md).
nlohmann::json result_json(const ResultContext& context);

/// A score summary for the terminal.
std::string result_summary(const ResultContext& context);

}  // namespace acdr
