// The moving part of a World's state, captured on the thread that steps the World so that
// another thread can draw it while stepping goes on (app/live_attempt.hpp). The constant parts
// (configuration, static solids, instrument geometry) are read from the World itself, which
// never changes them after construction.
#pragma once

#include <cstdint>
#include <vector>

#include "engine/world/world.hpp"

namespace acdr {

/// How a particle is drawn.
enum class ParticleClass : std::uint8_t { kTarget = 0, kProtected = 1, kRemoved = 2 };

/// Capacities are kept between captures, so a repeated capture does not allocate.
struct WorldState {
  Frame frame;
  std::vector<Collider> instrument;            ///< instrument colliders at the frame's pose
  std::vector<Eigen::Vector3f> positions;      ///< particle positions (m)
  std::vector<ParticleClass> particle_class;   ///< one per particle
  std::vector<std::uint8_t> material;          ///< one per particle: index into the materials
};

/// Copies the moving state of `world` into `out` (on the stepping thread).
void capture_world_state(const World& world, WorldState& out);

}  // namespace acdr
