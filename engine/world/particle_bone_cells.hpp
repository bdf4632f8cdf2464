// The particles' reaction on the bone as loads for the vertebrae's finite-element model: the
// force of every particle that presses on the bone grid, gathered per cubic cell of a given
// size and vertebra (the force summed, placed at the force-weighted mean of its particles; each
// particle on the vertebra whose surface is nearer). Fixed capacity: gathering allocates
// nothing. A pipelined world gathers them beside its steps and adds them to a later sample.
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "engine/core/bone_load.hpp"
#include "engine/core/types.hpp"

namespace acdr {

class SignedDistanceGrid;

struct ParticleBoneCells {
  static constexpr int kCapacity = BoneLoadSample::kCapacity;
  int count = 0;
  double cell_m = 0.0;
  std::array<std::int64_t, kCapacity> key{};  // cell and vertebra
  std::array<std::uint8_t, kCapacity> vertebra{};
  std::array<double, kCapacity> weight{};     // summed |force|
  std::array<Vec3, kCapacity> sum{};          // positions weighted by |force|
  std::array<Vec3, kCapacity> force{};        // summed forces

  /// Gathers the particles' forces on the bone (`forces[i]` at `x[i]`) into at most
  /// `capacity` cells of `cell_m`; once they are all taken, a particle in another cell joins
  /// the nearest one of its vertebra (the total force is kept).
  void gather(std::span<const Vec3> forces, std::span<const Vec3> x, const SignedDistanceGrid& c4,
              const SignedDistanceGrid& c5, double cell_m, int capacity);
  /// Appends the cells to `out` as nucleus loads; cells beyond its free places join the
  /// nearest kept cell of their vertebra.
  void append_to(BoneLoadSample& out) const;
};

}  // namespace acdr
