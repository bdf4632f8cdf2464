// A rubric's expert benchmarks measured on a cohort of expert attempts, as the MScore (expert
// mean and SD per metric) and NeuroVR (trimmed mean of the experts) set theirs
// (docs/assessment.md, "Calibration"; docs/references.md, Assessment anchors).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "assessment/attempt_result.hpp"
#include "assessment/rubric.hpp"

namespace acdr {

/// How benchmarks are computed from the experts' values of a metric.
struct CalibrationMethod {
  /// Share of the experts dropped at each end before the mean and SD (0: plain mean and SD;
  /// 0.2 of 5 experts drops none, of 10 drops the lowest and the highest). In [0, 0.5).
  double trim_fraction = 0.0;
  /// pass_score = 50 - 10 * pass_sds: an attempt that is, on the weighted average of its
  /// terms, this many expert SDs worse than the experts' mean still passes (1: LAP Mentor's
  /// rule is 2 SDs on each metric; the MScore passes on every metric within its band).
  double pass_sds = 1.0;
  /// task.min = task_share * the experts' mean of the task metric ("did the task" = removed
  /// at least a quarter of what the experts remove).
  double task_share = 0.25;
};

/// One metric's benchmark.
struct Benchmark {
  std::string metric;
  std::size_t experts = 0;  ///< values used (after trimming)
  double mean = 0.0;
  double measured_sd = 0.0;  ///< sample SD (n - 1) of the values used
  double sd = 0.0;           ///< what the rubric gets: measured_sd, or the term's sd_floor
  bool floored = false;      ///< sd is the floor, not the measured spread
  double min = 0.0, max = 0.0;  ///< range over all experts (before trimming)
};

struct Calibration {
  std::vector<Benchmark> terms;            ///< in the rubric's term order
  std::optional<Benchmark> task;           ///< the task metric's benchmark (when a task rule)
  std::optional<double> task_min;          ///< the new task rule's minimum
  double pass_score = 50.0;
  std::size_t experts = 0;
};

/// Benchmarks for every term of `rubric` (and its task metric) from the experts' metrics.
/// Needs at least two experts and every term's metric in each of them; otherwise nullopt
/// and `error` says which expert (by index, 1-based) lacks which metric.
std::optional<Calibration> calibrate(const Rubric& rubric, const std::vector<Metrics>& experts,
                                     const CalibrationMethod& method, std::string* error);

/// `rubric` with the calibrated means, SDs, task minimum and pass score; weights, directions,
/// safety flags, floors and gates kept.
Rubric apply_calibration(const Rubric& rubric, const Calibration& calibration);

/// Leave-one-out: expert i scored under the rubric calibrated on all the others.
struct LeaveOneOut {
  std::size_t expert = 0;  ///< index into the experts
  ScoreResult score;
};
std::optional<std::vector<LeaveOneOut>> leave_one_out(const Rubric& rubric,
                                                      const std::vector<Metrics>& experts,
                                                      const CalibrationMethod& method,
                                                      std::string* error);

}  // namespace acdr
