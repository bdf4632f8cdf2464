// What the renderer draws: plain geometry in world coordinates (metres), filled from a World
// or from a recording. The renderer knows nothing of the engine's classes.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace acdr {

/// How a surface's light reads, beyond its colour: particle materials get the look of their
/// tissue (the mesh shader's finishes).
enum class SurfaceFinish : std::uint8_t {
  kPlain,      ///< diffuse with a Blinn-Phong highlight of `specular` strength
  kWetGel,     ///< nucleus and removed lumps: a sharp wet highlight, soft light wrapping into
               ///< the shadowed side (a translucent gel), a bright rim at grazing angles
  kFibrous,    ///< annulus: concentric lamellae and fine oblique fibres around `pattern_axis`
  kCartilage,  ///< hyaline cartilage: smooth, a soft broad sheen, slight translucency
};

/// A triangle mesh drawn lit, in one colour. Vertices are in the mesh's local frame.
struct RenderMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::uint32_t> indices;  ///< triangles, counter-clockwise seen from outside
  /// Optional outward unit normals, one per vertex (local frame). Empty: the renderer computes
  /// them from the triangles, smooth across edges flatter than ~35 degrees and sharp across
  /// steeper ones (box edges stay crisp, spheres stay round).
  std::vector<Eigen::Vector3f> normals;
  Eigen::Affine3f pose = Eigen::Affine3f::Identity();
  Eigen::Vector4f rgba = Eigen::Vector4f(0.8f, 0.8f, 0.8f, 1.0f);  ///< a < 1: translucent
  float specular = 0.25f;  ///< strength of highlights, 0..1 (steel ~0.7, bone ~0.15)
  SurfaceFinish finish = SurfaceFinish::kPlain;
  /// kFibrous: the lamellae are rings around the line through `pattern_origin` along
  /// `pattern_axis` (world, m; the disc's centre and the spine's axis).
  Eigen::Vector3f pattern_origin = Eigen::Vector3f::Zero();
  Eigen::Vector3f pattern_axis = Eigen::Vector3f::UnitY();
  /// Non-zero: a promise that vertices, indices and normals are the same every time this id is
  /// drawn (pose and colour may change), so a renderer uploads them once and keeps them.
  /// 0: uploaded again on every frame (fine for small or changing meshes).
  std::uint64_t geometry_id = 0;
  /// Counted when a default camera frames the scene (frame_scene). Set false for parts that
  /// should not pull the view away from the work site, e.g. a long instrument shaft.
  bool include_in_framing = true;
};

/// Particles drawn as lit spheres (or sprites), one colour per particle.
struct RenderParticles {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector4f> colors;  ///< one per position (or empty: all `default_color`);
                                        ///< alpha 0 hides a particle, other alphas are opaque
  float radius_m = 0.5e-3f;
  Eigen::Vector4f default_color = Eigen::Vector4f(0.93f, 0.80f, 0.45f, 1.0f);
};

struct RenderCamera {
  Eigen::Vector3f eye = Eigen::Vector3f(0.06f, -0.08f, 0.07f);
  Eigen::Vector3f target = Eigen::Vector3f::Zero();
  Eigen::Vector3f up = Eigen::Vector3f(0.0f, 0.0f, 1.0f);
  float fov_y_deg = 35.0f;
  float near_m = 1.0e-3f;
  float far_m = 1.0f;
};

/// A ground plane the renderer adds under the scene as a depth cue: a faint grid on a plane
/// that fades out with distance, lit like the rest (it is not part of the physics).
struct RenderGround {
  bool visible = true;
  /// z of the plane (m); NaN: just under the lowest point of the scene.
  float height_m = std::numeric_limits<float>::quiet_NaN();
  Eigen::Vector3f rgb = Eigen::Vector3f(0.42f, 0.43f, 0.46f);
  float grid_spacing_m = 0.01f;  ///< distance between grid lines (m); 0: no grid
};

/// Shadows of the key light (a depth map from the light's side), a cue to how high the
/// instrument is above the material. Translucent meshes and the ground cast none.
struct RenderShadows {
  bool enabled = true;
  bool particles_cast = true;  ///< particles cast shadows too (a second pass over them)
  int map_size_px = 1024;      ///< side of the square depth map; more is sharper and slower
};

struct RenderScene {
  std::vector<RenderMesh> meshes;   ///< opaque first, translucent drawn after, back to front
  RenderParticles particles;
  RenderCamera camera;
  Eigen::Vector3f background = Eigen::Vector3f(0.12f, 0.13f, 0.16f);
  RenderGround ground;
  RenderShadows shadows;
};

}  // namespace acdr
