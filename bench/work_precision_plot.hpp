// The work-precision diagram as a picture: error against run time on log-log axes (as in
// the ODE-solver work-precision diagrams of Hairer & Wanner and the physics-engine
// speed/accuracy comparisons in docs/references.md), one colour per solver, drawn by a small
// rasteriser into an RGB buffer (the caller writes the PNG).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bench/bench_suite.hpp"

namespace acdr {

struct PlotImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< width * height * 3, top row first
};

/// Force RMS error (y) against wall seconds per simulated second (x) for every non-reference
/// point of `report`; errors below 1e-6 are drawn at 1e-6. A dashed line marks real time
/// (x = 1) and the 5 % error target.
PlotImage plot_work_precision(const BenchReport& report, int width = 1160, int height = 680);

}  // namespace acdr
