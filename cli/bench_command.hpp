// `acdr bench [--quick] [--csv FILE] [--json] [--png FILE] [--scene NAME=SCENARIO:TRAJECTORY]`:
// the work-precision benchmark (our solver over a grid of settings and Bullet's soft body as a
// peer, against a converged reference), cost against particle count, and the skips switched
// off and on. Prints a table (or JSON) on `out`, progress on `err`, and writes the CSV and the
// work-precision plot.
#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace acdr {

struct BenchOptions {
  bool quick = false;    ///< the small grid: about three minutes on a 2-core machine
  bool json = false;     ///< JSON on stdout instead of the table
  std::string csv;       ///< also write every figure as CSV here, when set
  std::string png = "bench_work_precision.png";  ///< the work-precision plot; empty: none
  /// NAME=SCENARIO:TRAJECTORY[@WINDOW_START_S[,RUN_FROM_S]] (the runs start at RUN_FROM_S,
  /// default the trajectory's start, and are compared and timed from WINDOW_START_S); empty:
  /// the box and the healthy C4-C5 modules on their demonstration trajectories.
  std::vector<std::string> scenes;
  bool render = true;    ///< measure the headless skip with an offscreen renderer
};

/// Returns 0 when the benchmark ran, 2 on bad input (a scene that cannot be loaded).
int run_bench(const BenchOptions& options, std::ostream& out, std::ostream& err);

}  // namespace acdr
