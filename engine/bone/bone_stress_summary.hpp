// What the bone's stresses over an attempt come to: the peaks per measured place and the time
// spent above a warning fraction of the bone's strength. Plain data; the assessment turns it
// into metrics (assessment/bone_metrics.hpp), the bone model fills it (bone_stress_history).
#pragma once

#include <array>
#include <cstdint>

namespace acdr {

/// Where the peaks are taken (docs/bone-fem.md, "Metrics").
enum class BoneMeasure : int {
  kC4InferiorEndplate = 0,  ///< C4's bony endplate on the C4-C5 disc
  kC5SuperiorEndplate = 1,  ///< C5's bony endplate on the C4-C5 disc
  kC4Posterior = 2,         ///< C4's pedicles and the bone around its foramina
  kC5Posterior = 3,         ///< the same on C5
};
inline constexpr int kBoneMeasureCount = 4;
const char* bone_measure_name(BoneMeasure measure);
/// 0 for C4's measures, 1 for C5's.
inline int bone_measure_vertebra(BoneMeasure m) {
  return (m == BoneMeasure::kC4InferiorEndplate || m == BoneMeasure::kC4Posterior) ? 0 : 1;
}
inline bool bone_measure_is_endplate(BoneMeasure m) {
  return m == BoneMeasure::kC4InferiorEndplate || m == BoneMeasure::kC5SuperiorEndplate;
}

/// Published strength figures the warnings are a fraction of (Pa; docs/bone-fem.md, Metrics).
struct BoneStrengths {
  /// The bony endplate: its modulus (1,000 MPa) times the compressive yield strain of
  /// vertebral bone, 0.77 % (Morgan & Keaveny 2001).
  double endplate_Pa = 7.7e6;
  /// The posterior elements: their modulus (3.5 GPa) times the same yield strain.
  double posterior_Pa = 27.0e6;
  /// Warning at this fraction of the strength.
  double warning_fraction = 0.5;
};

struct BoneStressSummary {
  std::array<double, kBoneMeasureCount> peak_Pa{};  ///< largest over the samples
  /// Time with the stress above warning_fraction * strength: each sample counts its period.
  double endplate_over_warning_s = 0.0;  ///< either endplate
  double posterior_over_warning_s = 0.0;
  double peak_load_N = 0.0;        ///< largest sum of load magnitudes of a sample
  double peak_load_t_s = 0.0;      ///< when (the dashboard's drill-down moment)
  double peak_stress_t_s = 0.0;    ///< when the larger endplate peak was reached
  std::int64_t samples = 0;        ///< load samples seen
  std::int64_t solves = 0;         ///< vertebra solves done (loaded vertebrae)
};

}  // namespace acdr
