// World -> RenderScene.
#include "ui/scene_snapshot.hpp"

#include <algorithm>
#include <cmath>
#include <string>

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
    case ColliderKind::kSdfGrid:
      return;  // bone: drawn from its triangle meshes (add_anatomy)
  }
  mesh.specular = specular;
  scene.meshes.push_back(std::move(mesh));
}

/// Frames the work area (static solids, particles, the instrument's working end) rather than
/// the whole scene, whose long shaft would make the disc space small in the picture.
RenderCamera frame_work_area(const World& world, const Frame& frame,
                             const std::vector<Eigen::Vector3f>& particles,
                             const RenderScene& scene, float aspect) {
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
  // Material near the walls belongs to the work area; a few stray particles flung far away
  // should not shrink the whole scene to a corner of the picture.
  const Eigen::AlignedBox3d walls = box;
  const double near_walls = 0.015;  // m
  for (const auto& p : particles) {
    const Vec3 x = p.cast<double>();
    if (walls.isEmpty() || walls.exteriorDistance(x) < near_walls) box.extend(x);
  }
  if (const InstrumentGeometry* instrument = world.instrument()) {
    const Pose grip = frame.instrument;
    const double reach = 0.3 * instrument->config().shaft_length_m;
    box.extend(grip.apply(instrument->working_point()));
    box.extend(grip.apply(instrument->working_point() + Vec3(0, 0, reach)));
  }
  if (box.isEmpty()) return frame_scene(scene, aspect);
  return frame_bounds(box.min().cast<float>(), box.max().cast<float>(), aspect);
}

/// The vertebrae as opaque bone and the danger zones as translucent solids.
void add_anatomy(RenderScene& scene, const Anatomy& anatomy, const Frame& frame,
                 const SceneStyle& style) {
  for (VertebraLevel level : {VertebraLevel::kC4, VertebraLevel::kC5}) {
    const TriangleMesh& bone = anatomy.vertebra(level);
    RenderMesh mesh;
    mesh.vertices.reserve(bone.vertices.size());
    for (const Vec3& v : bone.vertices) mesh.vertices.push_back(v.cast<float>());
    mesh.indices.reserve(3 * bone.triangles.size());
    for (const auto& t : bone.triangles) mesh.indices.insert(mesh.indices.end(), t.begin(), t.end());
    mesh.rgba = style.bone;
    mesh.specular = 0.15f;
    mesh.geometry_id = bone.content_hash() | 1u;  // static: uploaded once
    scene.meshes.push_back(std::move(mesh));
  }
  const auto& zones = anatomy.zones();
  for (std::size_t zi = 0; zi < zones.size(); ++zi) {
    const DangerZone& z = zones[zi];
    const std::string& n = z.name;
    Eigen::Vector4f rgba = n.find("artery") != std::string::npos ? style.artery
                           : n.find("root") != std::string::npos ? style.nerve
                           : n.find("cord") != std::string::npos ? style.cord
                                                                 : style.zone;
    // A zone turns its warning colour as the instrument comes within its warning
    // distance, and the danger colour (more opaque) once the instrument is inside it.
    if (static_cast<int>(zi) < frame.zone_count && zi < frame.zones.size()) {
      if (frame.zones[zi].inside)
        rgba = style.zone_inside;
      else if (frame.zones[zi].warning)
        rgba = style.zone_warning;
    }
    RenderMesh mesh;
    switch (z.shape) {
      case ZoneShape::kSphere:
        mesh = make_sphere(z.a_m.cast<float>(), static_cast<float>(z.radius_m), rgba);
        break;
      case ZoneShape::kCapsule:
        mesh = make_capsule(z.a_m.cast<float>(), z.b_m.cast<float>(), static_cast<float>(z.radius_m), rgba);
        if (z.bent) {
          append_mesh(mesh, make_capsule(z.b_m.cast<float>(), z.c_m.cast<float>(),
                                         static_cast<float>(z.radius_m), rgba));
        }
        break;
      case ZoneShape::kBox:
        mesh = make_rounded_box(z.half_extents_m.cast<float>(), static_cast<float>(z.radius_m),
                                to_affine(Pose{z.a_m, z.orientation}), rgba);
        if (n.find("cord") != std::string::npos) {
          // The cord itself inside the zone (the canal with its ligament and dura): an oval
          // about 12 x 7 mm across at C4-C5, drawn only, along the box's long axis (y).
          const Eigen::Vector3f h = z.half_extents_m.cast<float>();
          const Eigen::Vector3f c = z.a_m.cast<float>();
          RenderMesh cord = make_cylinder(c - Eigen::Vector3f(0, h.y(), 0), c + Eigen::Vector3f(0, h.y(), 0), 1.0f,
                                          Eigen::Vector4f(style.cord.x(), style.cord.y(), style.cord.z(), 0.85f));
          const float rx = std::min(6.0e-3f, 0.65f * h.x()), rz = std::min(3.6e-3f, 0.6f * h.z());
          for (Eigen::Vector3f& v : cord.vertices) {
            v.x() = c.x() + (v.x() - c.x()) * rx;
            v.z() = c.z() + (v.z() - c.z()) * rz;
          }
          cord.normals.clear();  // scaled: let the renderer recompute them
          cord.specular = 0.2f;
          scene.meshes.push_back(std::move(cord));
        }
        break;
      case ZoneShape::kSdfBand:
        continue;  // endplates: the bone itself shows them
    }
    mesh.specular = 0.1f;
    scene.meshes.push_back(std::move(mesh));
  }
}

/// The particle materials as surfaces: one per material still in place, one over all the
/// removed material. Each gets its tissue's colour and finish.
void add_material_surfaces(RenderScene& scene, const World& world, const WorldState& state,
                           const SceneStyle& style, MaterialSurfaceCache* cache) {
  const NucleusConfig& config = world.config().nucleus;
  const float spacing = static_cast<float>(config.spacing_m);
  const std::size_t materials = config.materials.size();
  constexpr std::uint64_t kRemovedKey = 0xffff;
  // Particle centres by group: materials in place 0..M-1, then the removed material.
  std::vector<std::vector<Eigen::Vector3f>> groups(materials + 1);
  for (std::size_t i = 0; i < state.positions.size(); ++i) {
    const std::size_t m = i < state.material.size() ? state.material[i] : 0;
    const bool removed = state.particle_class[i] == ParticleClass::kRemoved;
    groups[removed || m >= materials ? materials : m].push_back(state.positions[i]);
  }
  MaterialSurfaceCache local;
  MaterialSurfaceCache& surfaces = cache ? *cache : local;
  for (std::size_t g = 0; g <= materials; ++g) {
    if (groups[g].empty()) continue;
    const bool removed = g == materials;
    bool reused = false;
    const std::uint64_t key = removed ? kRemovedKey : g;
    const ParticleSurface& surface = surfaces.surface(key, groups[g], spacing, &reused);
    if (surface.indices.empty()) continue;
    RenderMesh mesh;
    mesh.vertices = surface.vertices;
    mesh.normals = surface.normals;
    mesh.indices = surface.indices;
    // A surface unchanged since the last frame keeps its GPU copy; a changing one is streamed
    // (an id per shape would fill the renderer's cache with shapes never drawn again).
    if (reused) mesh.geometry_id = (surfaces.hash(key) ^ (key * 0x9e3779b97f4a7c15ull)) | 1u;
    if (removed) {
      mesh.rgba = style.removed;
      mesh.finish = SurfaceFinish::kWetGel;
      mesh.specular = 0.8f;
    } else {
      const MaterialConfig& material = config.materials[g];
      const bool cartilage = material.name.find("cartilage") != std::string::npos ||
                             material.name.find("endplate") != std::string::npos;
      if (material.counts_as_target) {
        mesh.rgba = style.nucleus;
        mesh.finish = SurfaceFinish::kWetGel;
        mesh.specular = 0.8f;
      } else if (cartilage) {
        mesh.rgba = style.cartilage;
        mesh.finish = SurfaceFinish::kCartilage;
        mesh.specular = 0.45f;
      } else {
        mesh.rgba = style.annulus;
        mesh.finish = SurfaceFinish::kFibrous;
        mesh.specular = 0.3f;
        // Lamellae around the axis of the material's ring (or the scene's spine axis y).
        for (const ParticleBlockConfig& b : config.blocks) {
          if (b.material != static_cast<int>(g) || b.shape != BlockShape::kEllipticCylinder)
            continue;
          mesh.pattern_origin = b.center_m.cast<float>();
          mesh.pattern_axis = Eigen::Vector3f::Unit(std::clamp(b.axis, 0, 2));
          break;
        }
      }
    }
    scene.meshes.push_back(std::move(mesh));
  }
}

}  // namespace

RenderScene snapshot_world(const World& world, float aspect, const SceneStyle& style,
                           const SnapshotOptions& options) {
  WorldState state;
  capture_world_state(world, state);
  return snapshot_state(world, state, aspect, style, options);
}

RenderScene snapshot_state(const World& world, const WorldState& state, float aspect,
                           const SceneStyle& style, const SnapshotOptions& options) {
  RenderScene scene;
  const WorldConfig& config = world.config();
  scene.ground.visible = config.ground.enabled;
  if (config.ground.enabled) scene.ground.height_m = static_cast<float>(config.ground.height_m);

  for (const Collider& c : world.static_colliders()) {
    if (c.particles_only) add_collider(scene, c, style.ligament, 0.5f);  // anatomy
    else if (style.draw_walls) add_collider(scene, c, style.wall, 0.3f);
  }
  if (style.draw_instrument)
    for (const Collider& c : state.instrument) add_collider(scene, c, style.instrument, 0.7f);

  if (!state.positions.empty() && options.drawing == MaterialDrawing::kSurfaces) {
    add_material_surfaces(scene, world, state, style, options.cache);
  } else if (!state.positions.empty()) {
    scene.particles.radius_m = static_cast<float>(0.5 * config.nucleus.spacing_m);
    scene.particles.positions = state.positions;
    scene.particles.colors.reserve(state.positions.size());
    for (ParticleClass c : state.particle_class) {
      scene.particles.colors.push_back(c == ParticleClass::kRemoved  ? style.removed
                                       : c == ParticleClass::kTarget ? style.nucleus
                                                                     : style.annulus);
    }
  }
  if (const Anatomy* anatomy = world.anatomy())
    add_anatomy(scene, *anatomy, state.frame, style);
  // Translucent meshes last (the renderer sorts them back to front).
  std::stable_partition(scene.meshes.begin(), scene.meshes.end(),
                        [](const RenderMesh& m) { return m.rgba.w() >= 1.0f; });
  scene.camera = frame_work_area(world, state.frame, state.positions, scene, aspect);
  if (const Anatomy* anatomy = world.anatomy()) {
    // anatomy: the surgeon's view, from anterior (+z, up), a little to the left
    // and caudal, framing the disc space and the foramina; the spine runs up the image.
    const SegmentLandmarks& l = anatomy->landmarks();
    const float reach = static_cast<float>(std::abs(l.foramen_transversarium_m[0].x()) + 6e-3);
    const Eigen::Vector3f lo(-reach, -14e-3f, static_cast<float>(l.body_back_z_m) - 6e-3f);
    const Eigen::Vector3f hi(reach, 14e-3f, static_cast<float>(l.body_front_z_m) + 4e-3f);
    scene.camera = frame_bounds(lo, hi, aspect, Eigen::Vector3f(0.4f, -0.2f, 1.0f));
    scene.camera.up = Eigen::Vector3f(0.0f, 1.0f, 0.0f);
    scene.camera.far_m = std::max(scene.camera.far_m, 0.5f);
  }
  return scene;
}

}  // namespace acdr
