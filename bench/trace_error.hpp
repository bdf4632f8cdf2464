// Errors of a benchmark run against a reference run of the same scene and window: relative
// RMS and peak error of the instrument force over time, and the error in nucleus removed.
#pragma once

#include "bench/scene_run.hpp"

namespace acdr {

struct TraceError {
  /// sqrt(sum |F - F_ref|^2 / sum |F_ref|^2) over the force windows both runs have.
  double force_rms = 0.0;
  /// max |F - F_ref| / max |F_ref|.
  double force_peak = 0.0;
  /// |removed fraction - reference removed fraction| (fractions of the initial nucleus).
  double removed = 0.0;
  std::size_t windows = 0;  ///< force windows compared
};

/// Compares `run` with `reference` window by window. A run that failed or stopped early is
/// compared over the windows it has and gets force_rms = 1 at least (it is not a usable
/// answer).
TraceError trace_error(const RunTrace& run, const RunTrace& reference);

}  // namespace acdr
