// Loading a scenario file: JSON text -> a validated, immutable ScenarioModel in SI units, or
// every problem found, each located by line and JSON path (docs/scenario-format.md).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "engine/core/input_file.hpp"
#include "scenarios/key_registry.hpp"
#include "scenarios/scenario_error.hpp"
#include "scenarios/scenario_model.hpp"

namespace acdr {

/// Either a model (and no errors) or errors (and no model).
struct LoadResult {
  std::shared_ptr<const ScenarioModel> model;  ///< null when anything is wrong
  std::vector<ScenarioError> errors;           ///< sorted by line

  bool ok() const { return model != nullptr; }
};

/// Reads and validates `path`. A missing or unreadable file is one error.
LoadResult load_scenario_file(const std::string& path);

/// Validates `text`; errors name `path_for_messages`. The model's `path` is that name and its
/// `hash` the FNV-1a 64 of `text`.
LoadResult load_scenario_text(const std::string& text, const std::string& path_for_messages);

/// The same, recording every key the loader reads into `registry` (for the schema sync test).
LoadResult load_scenario_text(const std::string& text, const std::string& path_for_messages,
                              KeyRegistry* registry);

}  // namespace acdr
