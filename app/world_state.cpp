// Capturing the moving part of a World.
#include "app/world_state.hpp"

namespace acdr {

void capture_world_state(const World& world, WorldState& out) {
  out.frame = world.last_frame();
  out.instrument.assign(world.instrument_colliders().begin(), world.instrument_colliders().end());
  // As the last particle step handed on left them: a pipelined step in flight is not waited for.
  const auto positions = world.particle_positions();
  const auto materials = world.particle_materials();
  const WorldConfig& config = world.config();
  out.positions.resize(positions.size());
  out.particle_class.resize(positions.size());
  out.material.assign(materials.begin(), materials.end());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    out.positions[i] = positions[i].cast<float>();
    const bool target = materials[i] < config.nucleus.materials.size() &&
                        config.nucleus.materials[materials[i]].counts_as_target;
    out.particle_class[i] = world.removed_at(positions[i]) ? ParticleClass::kRemoved
                            : target                       ? ParticleClass::kTarget
                                                           : ParticleClass::kProtected;
  }
}

}  // namespace acdr
