// Force and removal errors between two runs.
#include "bench/trace_error.hpp"

#include <algorithm>
#include <cmath>

namespace acdr {

TraceError trace_error(const RunTrace& run, const RunTrace& reference) {
  TraceError e;
  const std::size_t n = std::min(run.force_N.size(), reference.force_N.size());
  double diff2 = 0.0, ref2 = 0.0, diff_max = 0.0, ref_max = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double d = (run.force_N[k] - reference.force_N[k]).norm();
    const double r = reference.force_N[k].norm();
    diff2 += d * d;
    ref2 += r * r;
    diff_max = std::max(diff_max, d);
    ref_max = std::max(ref_max, r);
  }
  e.windows = n;
  e.force_rms = ref2 > 0.0 ? std::sqrt(diff2 / ref2) : (diff2 > 0.0 ? 1.0 : 0.0);
  e.force_peak = ref_max > 0.0 ? diff_max / ref_max : (diff_max > 0.0 ? 1.0 : 0.0);
  e.removed = std::abs(run.removed_fraction - reference.removed_fraction);
  if (run.failed || n < reference.force_N.size()) e.force_rms = std::max(e.force_rms, 1.0);
  return e;
}

}  // namespace acdr
