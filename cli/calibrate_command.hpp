// `acdr calibrate`: a module's rubric benchmarks from an expert cohort (assessment/calibration.hpp):
// the experts' attempts in a training record, or the module's expert demonstrations replayed.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace acdr {

struct CalibrateOptions {
  std::string scenario;               ///< the module file whose rubric is calibrated
  std::vector<std::string> records;   ///< training records (database files), pooled; or
  std::vector<std::string> trainees;  ///< with record: only these trainees' attempts
  std::string demonstrations;         ///< a folder of expert_*.csv trajectories
  double trim_fraction = 0.0;
  double pass_sds = 1.0;
  double task_share = 0.25;
  bool write = false;                 ///< put the calibrated rubric into the module file
  std::string out;                    ///< also write the rubric fragment to this file
  bool leave_one_out = false;         ///< score each expert against the others' benchmarks
};

/// Prints the benchmarks and the rubric fragment. Exit codes: 0 done, 2 bad input (module
/// file, record, folder, too few experts or a metric they lack).
int run_calibrate(const CalibrateOptions& options, std::ostream& out, std::ostream& err);

}  // namespace acdr
