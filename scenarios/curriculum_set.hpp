// The modules of one curriculum, from a folder of scenario files: every scenario file in the
// folder whose `curriculum` is the given id. The record learns the whole curriculum from it
// before the first attempt, so a module's prerequisites are known (and its lock holds) even on
// a new record where nothing has been attempted yet.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "scenarios/scenario_model.hpp"

namespace acdr {

struct CurriculumSet {
  /// The curriculum's modules, in module_order (then file name); one per module id.
  std::vector<std::shared_ptr<const ScenarioModel>> modules;
  /// Files of the folder that could not be read as scenarios, or that repeat a module id
  /// already taken: one line each, naming the file. The caller decides whether to warn.
  std::vector<std::string> skipped;
};

/// Scenario files (`*.json`) of `directory` with `curriculum == curriculum_id`. A missing or
/// unreadable folder is one line of `skipped`.
CurriculumSet load_curriculum_set(const std::string& directory, const std::string& curriculum_id);

}  // namespace acdr
