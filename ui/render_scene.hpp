// What the renderer draws: plain geometry in world coordinates (metres), filled from a World
// or from a recording. The renderer knows nothing of the engine's classes.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace acdr {

/// A triangle mesh drawn lit, in one colour. Vertices are in the mesh's local frame.
struct RenderMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::uint32_t> indices;  ///< triangles, counter-clockwise seen from outside
  Eigen::Affine3f pose = Eigen::Affine3f::Identity();
  Eigen::Vector4f rgba = Eigen::Vector4f(0.8f, 0.8f, 0.8f, 1.0f);  ///< a < 1: translucent
};

/// Particles drawn as lit spheres (or sprites), one colour per particle.
struct RenderParticles {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector4f> colors;
  float radius_m = 0.5e-3f;
};

struct RenderCamera {
  Eigen::Vector3f eye = Eigen::Vector3f(0.06f, -0.08f, 0.07f);
  Eigen::Vector3f target = Eigen::Vector3f::Zero();
  Eigen::Vector3f up = Eigen::Vector3f(0.0f, 0.0f, 1.0f);
  float fov_y_deg = 35.0f;
  float near_m = 1.0e-3f;
  float far_m = 1.0f;
};

struct RenderScene {
  std::vector<RenderMesh> meshes;   ///< opaque first, translucent drawn after, back to front
  RenderParticles particles;
  RenderCamera camera;
  Eigen::Vector3f background = Eigen::Vector3f(0.12f, 0.13f, 0.16f);
};

}  // namespace acdr
