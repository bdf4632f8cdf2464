// What the bone's finite-element model costs per load update in a real attempt: a scene that
// models the bone is run along its trajectory window, every load sample the world takes is
// kept, and each is then solved the way the attempt's worker thread solves it (both vertebrae,
// the stresses the metrics read), timed per vertebra solve in CPU time of this thread and in
// wall time. For `acdr bench` (its "Bone" table); the cost per mesh size of a single contact is
// acdr_bone_fem_bench's.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "engine/bone/bone_segment.hpp"
#include "engine/core/bone_load.hpp"
#include "engine/devices/trajectory.hpp"

namespace acdr {

struct BenchScene;
struct RunWindow;
struct WorldConfig;

/// Percentiles of a set of timings (ms).
struct TimingSummary {
  double median_ms = 0.0, mean_ms = 0.0, p95_ms = 0.0, max_ms = 0.0;
};
TimingSummary summarize_ms(std::vector<double> ms);

/// Cost of the bone solves along one scene's window.
struct BoneSolveFigures {
  std::string scene;
  bool measured = false;
  std::string note;                           ///< why not measured, when not
  double element_size_m = 0.0;
  std::array<std::size_t, 2> free_dofs{};     ///< C4, C5
  std::array<std::size_t, 2> factor_nonzeros{};
  /// Share of the factor's non-zeros the back substitution of the measured elements reads.
  std::array<double, 2> back_substitution_share{};
  double build_s = 0.0;                       ///< both vertebrae (cache load, factorisation)
  std::size_t samples = 0;                    ///< load samples in the window
  std::size_t solves = 0;                     ///< vertebra solves (loaded vertebrae)
  double mean_loads_per_solve = 0.0;          ///< patch loads on a solved vertebra
  TimingSummary solve_cpu, solve_wall;        ///< per vertebra solve: one load update
  TimingSummary sample_cpu, sample_wall;      ///< per loaded sample (one or both vertebrae)
};

/// The load samples a World takes along `trajectory` over `window` (empty when the scenario's
/// anatomy takes none).
std::vector<BoneLoadRecord> sample_bone_loads(const WorldConfig& world, const Trajectory& trajectory,
                                              const RunWindow& window);

/// Solves `samples` on `bone` as the attempt's worker does and times each vertebra solve.
/// `repeats` >= 1 solves the whole series that many times (the fastest of each solve is kept:
/// the work is the same, the spread is the host's).
BoneSolveFigures time_bone_solves(const BoneSegment& bone,
                                  const std::vector<BoneLoadRecord>& samples, int repeats = 1);

}  // namespace acdr
