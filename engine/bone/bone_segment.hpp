// The C4-C5 segment's bone as two finite-element vertebrae, ready for the loads an attempt
// samples (engine/core/bone_load.hpp): built from the anatomy's own surfaces, each load sample
// becomes one solve per loaded vertebra, and the peaks of the von Mises stress are taken where
// the instrument can hurt the bone: the bony endplate that faces the disc (C4 inferior, C5
// superior) and the posterior elements near the pedicles and the foramina.
//
// Threads: a built BoneSegment is immutable; `solve` writes only the caller's scratch, so a
// worker thread may own the calls (docs/bone-fem.md, "In an attempt").
#pragma once

#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "engine/anatomy/anatomy.hpp"
#include "engine/bone/bone_fem.hpp"
#include "engine/bone/bone_stress_summary.hpp"
#include "engine/core/bone_load.hpp"

namespace acdr {

/// How the bone is modelled in an attempt (SI; scenario keys under anatomy.bone).
struct BoneModelConfig {
  bool enabled = false;
  BoneFemConfig fem;
  /// Loads are sampled and solved every this much simulated time (s).
  double sample_period_s = 0.01;
  /// The nucleus's reaction is gathered over cubic cells this wide (m), one load per cell.
  double nucleus_cell_m = 2.0e-3;
  /// A vertebra whose loads add up (in magnitude) to less than this is not solved: its stress
  /// is taken as zero (N).
  double min_load_N = 0.01;
  BoneStrengths strengths;
};

/// "" when usable, else one "key: got ..., expected ..." line per problem (SI names).
std::string validate_bone_model_config(const BoneModelConfig& config);

/// What one load sample gave, per vertebra (0 C4, 1 C5).
struct BoneSampleResult {
  double t_s = 0.0;
  std::array<double, kBoneMeasureCount> peak_Pa{};  ///< per BoneMeasure
  double load_N = 0.0;                              ///< sum of the load magnitudes
  std::array<bool, 2> solved{};                     ///< vertebra solved (loaded)
  /// What each vertebra's solve took: CPU time of the solving thread and wall time (s).
  std::array<double, 2> cpu_s{}, wall_s{};
};

/// Per-thread workspace of the solves (no allocation once warm).
struct BoneSegmentScratch {
  std::array<BoneSolution, 2> solution;
  std::vector<ContactLoad> contacts;
  /// Everything, with the per-node stresses (for drawing). Off (the default): only the
  /// measured elements' stresses and the displacements they need (BoneFem::solve's `partial`),
  /// all the metrics read; the rest of the solutions is NaN.
  bool nodal_fields = false;
};

class BoneSegment {
 public:
  /// Builds both vertebrae from the anatomy's surfaces (meshes cached in `cache_dir`; "" none).
  /// Returns null with `error` set when a vertebra cannot be meshed or the config is bad.
  static std::unique_ptr<BoneSegment> build(const Anatomy& anatomy, const BoneModelConfig& config,
                                            const std::string& cache_dir, std::string* error);

  /// Solves the loaded vertebrae for one sample's loads; the solutions stay in `scratch`.
  BoneSampleResult solve(double t_s, std::span<const BoneLoadPoint> loads,
                         BoneSegmentScratch& scratch) const;

  const BoneFem& vertebra(int v) const { return *fem_[v]; }
  const BoneModelConfig& config() const { return config_; }
  /// Elements of each measure (indices into vertebra(measure_vertebra(m)).mesh().tets).
  const std::vector<std::uint32_t>& measure_elements(BoneMeasure m) const {
    return elements_[static_cast<int>(m)];
  }
  /// The partial solve of vertebra v: the elements of its measures.
  const PartialSolve& measured_solve(int v) const { return measured_[v]; }
  /// Seconds building took (meshing or cache, factorisation), both vertebrae.
  double build_seconds() const { return build_seconds_; }

 private:
  BoneModelConfig config_;
  std::array<std::unique_ptr<BoneFem>, 2> fem_;
  std::array<std::vector<std::uint32_t>, kBoneMeasureCount> elements_;
  std::array<PartialSolve, 2> measured_;  // per vertebra: the solve of its measured elements
  double build_seconds_ = 0.0;
};

/// The elements of `measure` in `fem` (a vertebra of the measure's level): endplate tetrahedra
/// on the disc side of the body's centre; posterior-element tetrahedra within `reach_m` behind
/// the body's posterior wall (pedicles, the transverse processes around the foramina
/// transversaria), not the laminae and the spinous process further back.
std::vector<std::uint32_t> bone_measure_elements(const BoneFem& fem, BoneMeasure measure,
                                                 double reach_m = 6.0e-3);

}  // namespace acdr
