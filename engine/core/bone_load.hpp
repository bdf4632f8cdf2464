// Loads on the bone, as the world samples them for the vertebrae's finite-element model
// (engine/bone): where the instrument and the nucleus press on C4 and C5, and with what force.
// Plain data of fixed size, filled inside the step without allocating; the attempt keeps each
// sample in its recording so the bone's stresses can be computed again from it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "engine/core/types.hpp"

namespace acdr {

/// Where a bone load comes from.
enum class BoneLoadSource : std::uint8_t {
  kInstrument = 0,  ///< a rigid contact point of the instrument with the bone (Bullet)
  kNucleus = 1,     ///< the particles' reaction on the bone, gathered over a small cell
};

/// One load on one vertebra, in the segment (world) frame. SI units, single precision: what
/// the recording stores is exactly what a live solve used (a rescore gives the same bits).
struct BoneLoadPoint {
  Eigen::Vector3f point_m = Eigen::Vector3f::Zero();  ///< where it acts (on or near the bone)
  Eigen::Vector3f force_N = Eigen::Vector3f::Zero();  ///< force on the bone
  float radius_m = 0.0f;  ///< radius of the patch it is spread over (0: the model's default)
  std::uint8_t vertebra = 0;    ///< 0 C4, 1 C5
  BoneLoadSource source = BoneLoadSource::kInstrument;
};

/// One sample of every load on the bone at a step (fixed capacity: no allocation).
struct BoneLoadSample {
  static constexpr int kCapacity = 160;
  double t_s = 0.0;
  std::int32_t count = 0;
  std::int32_t dropped = 0;  ///< instrument points beyond the capacity (not kept)
  std::array<BoneLoadPoint, kCapacity> points{};
};

/// A sample as an attempt's recording keeps it (only the loads present).
struct BoneLoadRecord {
  double t_s = 0.0;
  std::vector<BoneLoadPoint> points;
};

}  // namespace acdr
