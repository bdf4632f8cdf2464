// What a scenario will cost before anything is built, from its own numbers: particles, bonds,
// distance-grid cells, recording frames and the memory they take; and the budget `acdr
// validate` holds every scenario to, so that whatever validates also runs (within 4 GB of
// address space). The figures and the reasoning behind them: docs/scenario-format.md, Limits.
#pragma once

#include <string>

#include "scenarios/scenario_model.hpp"

namespace acdr {

/// Estimated cost of running a scenario. Counts are upper estimates from the scenario's
/// numbers (block sizes and spacing, grid spacing and margin over its region, time limit and
/// step); `bytes` is the estimated peak memory of a run, the program itself included.
struct ScenarioCost {
  double particles = 0.0;         ///< nucleus particles over all blocks
  double bonds = 0.0;             ///< bonds at the start (lattice neighbours within the bond radius)
  /// Samples of the bone's distance grid, the two vertebra grids of the zones, and (generated
  /// vertebrae) the grids each vertebra is meshed from.
  double grid_cells = 0.0;
  double vertebra_samples = 0.0;  ///< the part of grid_cells that meshes generated vertebrae
  double recording_frames = 0.0;  ///< one per step, up to the time limit or the recording cap
  double bytes = 0.0;             ///< estimated peak memory of a run
};

/// The budget. Each figure alone, and the memory of all together, must stay within it.
struct ScenarioBudget {
  /// Particles: what fits the memory budget beside a recording without a time limit (about
  /// 6 kB each); a hundred times the bundled modules' 3,000, and far beyond what steps in real
  /// time (a ceiling, not a target).
  static constexpr double kParticles = 300000.0;
  /// Bonds: about 100 bytes each; the particle budget at a bond radius of 2.2 spacings.
  static constexpr double kBonds = 10.0e6;
  /// Grid samples over the distance grids and the generated vertebrae's grids (a bundled module
  /// uses 3.2 million; the default region at a 0.1 mm spacing 17.4 million).
  static constexpr double kGridCells = 20.0e6;
  /// Recorded frames: one per step. With no time limit an attempt ends at this many steps
  /// (about 16.7 minutes at 1 ms).
  static constexpr double kRecordingFrames = 1.0e6;
  /// Estimated peak memory (bytes), the program's own 250 MB included: a gigabyte short of a
  /// 4 GB address-space limit (`ulimit -v 4000000`), for what the estimate misses.
  static constexpr double kBytes = 3.0e9;
};

/// Steps an attempt may take when its scenario sets no time limit (the recording cap).
inline constexpr std::size_t kMaxRecordingFrames = static_cast<std::size_t>(ScenarioBudget::kRecordingFrames);

/// The cost of `model` (a validated scenario, or one read so far: only its numbers are used).
ScenarioCost estimate_cost(const ScenarioModel& model);

/// Lattice neighbours of a site within `factor` spacings (excluding itself): the bonds a
/// particle deep inside a block starts with.
int lattice_neighbours_within(double factor);

/// "about 3000 particles, 27000 bonds, 0 grid samples, 60000 frames, 450 MB": the cost in one line.
std::string cost_summary(const ScenarioCost& cost);

/// "1.2 GB", "350 MB", "12 kB": a byte figure for messages.
std::string format_bytes(double bytes);

}  // namespace acdr
