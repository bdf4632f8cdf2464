// World -> RenderScene.
#include "ui/scene_snapshot.hpp"

#include <algorithm>

#include "ui/mesh_primitives.hpp"
#include "ui/render_camera.hpp"

namespace acdr {
namespace {

Eigen::Affine3f to_affine(const Pose& p) {
  Eigen::Affine3f a = Eigen::Affine3f::Identity();
  a.translate(p.position.cast<float>());
  a.rotate(p.orientation.cast<float>());
  return a;
}

void add_collider(RenderScene& scene, const Collider& c, const Eigen::Vector4f& rgba,
                  float specular) {
  RenderMesh mesh;
  switch (c.kind) {
    case ColliderKind::kHalfSpace:
      return;  // drawn as the renderer's ground plane
    case ColliderKind::kBox:
      mesh = make_oriented_box(c.half_extents_m.cast<float>(), to_affine(c.pose), rgba);
      break;
    case ColliderKind::kCapsule: {
      const Vec3 a = c.pose.apply(Vec3(0, 0, -c.half_length_m));
      const Vec3 b = c.pose.apply(Vec3(0, 0, c.half_length_m));
      mesh = make_capsule(a.cast<float>(), b.cast<float>(), static_cast<float>(c.radius_m), rgba);
      break;
    }
    case ColliderKind::kCupShell: {
      const Vec3 opening = c.pose.orientation * Vec3::UnitZ();
      mesh = make_cup_shell(c.pose.position.cast<float>(), opening.cast<float>(),
                            static_cast<float>(c.radius_m - c.thickness_m),
                            static_cast<float>(c.thickness_m), rgba);
      break;
    }
  }
  mesh.specular = specular;
  scene.meshes.push_back(std::move(mesh));
}

/// Frames the work area (static solids, particles, the instrument's working end) rather than
/// the whole scene, whose long shaft would make the disc space small in the picture.
RenderCamera frame_work_area(const World& world, const Frame& frame, const RenderScene& scene,
                             float aspect) {
  Eigen::AlignedBox3d box;
  for (const Collider& c : world.static_colliders()) {
    if (c.kind != ColliderKind::kBox) continue;
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 local((corner & 1 ? 1 : -1) * c.half_extents_m.x(),
                       (corner & 2 ? 1 : -1) * c.half_extents_m.y(),
                       (corner & 4 ? 1 : -1) * c.half_extents_m.z());
      box.extend(c.pose.apply(local));
    }
  }
  for (const auto& p : scene.particles.positions) box.extend(p.cast<double>());
  if (const InstrumentGeometry* instrument = world.instrument()) {
    const Pose grip = frame.instrument;
    const double reach = 0.3 * instrument->config().shaft_length_m;
    box.extend(grip.apply(instrument->working_point()));
    box.extend(grip.apply(instrument->working_point() + Vec3(0, 0, reach)));
  }
  if (box.isEmpty()) return frame_scene(scene, aspect);
  return frame_bounds(box.min().cast<float>(), box.max().cast<float>(), aspect);
}

}  // namespace

void capture_world_state(const World& world, WorldState& out) {
  out.frame = world.last_frame();
  out.instrument.assign(world.instrument_colliders().begin(), world.instrument_colliders().end());
  const Nucleus* nucleus = world.nucleus();
  if (!nucleus) {
    out.positions.clear();
    out.particle_class.clear();
    return;
  }
  const WorldConfig& config = world.config();
  const auto positions = nucleus->positions();
  const auto materials = nucleus->materials();
  out.positions.resize(positions.size());
  out.particle_class.resize(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    out.positions[i] = positions[i].cast<float>();
    const bool target = materials[i] < config.nucleus.materials.size() &&
                        config.nucleus.materials[materials[i]].counts_as_target;
    out.particle_class[i] = world.is_removed(i) ? ParticleClass::kRemoved
                            : target           ? ParticleClass::kTarget
                                               : ParticleClass::kProtected;
  }
}

RenderScene snapshot_world(const World& world, float aspect, const SceneStyle& style) {
  WorldState state;
  capture_world_state(world, state);
  return snapshot_state(world, state, aspect, style);
}

RenderScene snapshot_state(const World& world, const WorldState& state, float aspect,
                           const SceneStyle& style) {
  RenderScene scene;
  const WorldConfig& config = world.config();
  scene.ground.visible = config.ground.enabled;
  if (config.ground.enabled) scene.ground.height_m = static_cast<float>(config.ground.height_m);

  for (const Collider& c : world.static_colliders()) add_collider(scene, c, style.wall, 0.3f);
  for (const Collider& c : state.instrument) add_collider(scene, c, style.instrument, 0.7f);

  if (!state.positions.empty()) {
    scene.particles.radius_m = static_cast<float>(0.5 * config.nucleus.spacing_m);
    scene.particles.positions = state.positions;
    scene.particles.colors.reserve(state.positions.size());
    for (ParticleClass c : state.particle_class) {
      scene.particles.colors.push_back(c == ParticleClass::kRemoved  ? style.removed
                                       : c == ParticleClass::kTarget ? style.nucleus
                                                                     : style.annulus);
    }
  }
  // Translucent meshes last (the renderer sorts them back to front).
  std::stable_partition(scene.meshes.begin(), scene.meshes.end(),
                        [](const RenderMesh& m) { return m.rgba.w() >= 1.0f; });
  scene.camera = frame_work_area(world, state.frame, scene, aspect);
  return scene;
}

}  // namespace acdr
