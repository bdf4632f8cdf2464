// The expert attempts a module's benchmarks are calibrated on (assessment/calibration.hpp):
// completed attempts from a training record, or the module's bundled expert demonstrations
// replayed through it. Also the text report of a calibration.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "assessment/attempt_result.hpp"
#include "assessment/calibration.hpp"
#include "scenarios/scenario_model.hpp"

namespace acdr {

/// One expert attempt: where it came from, and its metrics.
struct CohortAttempt {
  std::string label;  ///< "attempt 12 (t-0042)" or the demonstration's file name
  Metrics metrics;
};

/// Completed attempts at `module_id` in the record at `db_path`, by any of `trainees` (empty:
/// by anyone, practice attempts included), in start order. nullopt with `error` set when the
/// record cannot be read.
std::optional<std::vector<CohortAttempt>> cohort_from_record(const std::string& db_path,
                                                             const std::string& module_id,
                                                             const std::vector<std::string>& trainees,
                                                             std::string* error);

/// The files `dir`/expert_*.csv, sorted by name. nullopt with `error` set when the folder
/// cannot be read or holds none.
std::optional<std::vector<std::string>> expert_demonstrations(const std::string& dir,
                                                              std::string* error);

/// Each trajectory replayed through `scenario` headless (as `acdr run --headless`), with the
/// bone metrics where the scenario models the bone. `progress` (optional) is told each file as
/// it starts. nullopt with `error` set for a file that cannot be read or a run whose bone model
/// failed.
std::optional<std::vector<CohortAttempt>> cohort_from_trajectories(
    const ScenarioModel& scenario, const std::vector<std::string>& trajectories,
    std::string* error, const std::function<void(const std::string&)>& progress = {});

/// A table of the benchmarks: per term the metric, the experts used, their mean, measured SD,
/// the SD given to the rubric (marked when it is the floor), and their range; then the task
/// rule and the pass score.
std::string calibration_table(const Rubric& rubric, const Calibration& calibration);

}  // namespace acdr
