// Camera matrices and framing.
#include "ui/render_camera.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace acdr {

namespace {
constexpr float kPi = 3.14159265358979f;

// An orthonormal camera basis: forward (eye -> target), right, true up.
struct Basis {
  Eigen::Vector3f forward, right, up;
};

Basis camera_basis(const Eigen::Vector3f& eye, const Eigen::Vector3f& target,
                   const Eigen::Vector3f& up_hint) {
  Basis b;
  b.forward = target - eye;
  if (b.forward.squaredNorm() < 1e-20f) b.forward = Eigen::Vector3f(0, 1, 0);
  b.forward.normalize();
  b.right = b.forward.cross(up_hint);
  // Looking straight along `up` leaves no horizon; pick any perpendicular so the matrix stays
  // valid instead of filling with NaN.
  if (b.right.squaredNorm() < 1e-12f) b.right = b.forward.unitOrthogonal();
  b.right.normalize();
  b.up = b.right.cross(b.forward);
  return b;
}
}  // namespace

Eigen::Matrix4f view_matrix(const RenderCamera& camera) {
  const Basis b = camera_basis(camera.eye, camera.target, camera.up);
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m.block<1, 3>(0, 0) = b.right.transpose();
  m.block<1, 3>(1, 0) = b.up.transpose();
  m.block<1, 3>(2, 0) = -b.forward.transpose();
  m(0, 3) = -b.right.dot(camera.eye);
  m(1, 3) = -b.up.dot(camera.eye);
  m(2, 3) = b.forward.dot(camera.eye);
  return m;
}

Eigen::Matrix4f projection_matrix(const RenderCamera& camera, float aspect) {
  // gluPerspective's matrix.
  const float f = 1.0f / std::tan(0.5f * camera.fov_y_deg * kPi / 180.0f);
  const float n = camera.near_m;
  const float fa = camera.far_m;
  Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
  m(0, 0) = f / std::max(aspect, 1e-6f);
  m(1, 1) = f;
  m(2, 2) = (fa + n) / (n - fa);
  m(2, 3) = 2.0f * fa * n / (n - fa);
  m(3, 2) = -1.0f;
  return m;
}

std::optional<Eigen::Vector2f> project_to_pixel(const RenderCamera& camera, int width, int height,
                                                const Eigen::Vector3f& world) {
  const float aspect = static_cast<float>(width) / static_cast<float>(std::max(height, 1));
  const Eigen::Vector4f clip =
      projection_matrix(camera, aspect) * view_matrix(camera) * world.homogeneous();
  if (clip.w() <= 0.0f) return std::nullopt;
  const float x_ndc = clip.x() / clip.w();
  const float y_ndc = clip.y() / clip.w();
  return Eigen::Vector2f(0.5f * (x_ndc + 1.0f) * width, 0.5f * (1.0f - y_ndc) * height);
}

std::optional<Bounds3f> scene_bounds(const RenderScene& scene, bool framing_only) {
  Bounds3f b;
  b.min.setConstant(std::numeric_limits<float>::infinity());
  b.max.setConstant(-std::numeric_limits<float>::infinity());
  bool any = false;
  for (const RenderMesh& mesh : scene.meshes) {
    if (framing_only && !mesh.include_in_framing) continue;
    for (const Eigen::Vector3f& v : mesh.vertices) {
      const Eigen::Vector3f w = mesh.pose * v;
      b.min = b.min.cwiseMin(w);
      b.max = b.max.cwiseMax(w);
      any = true;
    }
  }
  const RenderParticles& p = scene.particles;
  const bool per_particle_colour = p.colors.size() == p.positions.size();
  for (std::size_t i = 0; i < p.positions.size(); ++i) {
    const float alpha = per_particle_colour ? p.colors[i].w() : p.default_color.w();
    if (alpha <= 0.0f) continue;
    b.min = b.min.cwiseMin(p.positions[i] - Eigen::Vector3f::Constant(p.radius_m));
    b.max = b.max.cwiseMax(p.positions[i] + Eigen::Vector3f::Constant(p.radius_m));
    any = true;
  }
  if (!any) return std::nullopt;
  return b;
}

RenderCamera frame_bounds(const Eigen::Vector3f& min, const Eigen::Vector3f& max, float aspect,
                          const Eigen::Vector3f& view_direction, float fov_y_deg, float margin) {
  RenderCamera camera;
  camera.fov_y_deg = fov_y_deg;
  camera.up = Eigen::Vector3f(0, 0, 1);
  camera.target = 0.5f * (min + max);
  Eigen::Vector3f back = view_direction;
  if (back.squaredNorm() < 1e-20f) back = default_view_direction();
  back.normalize();
  const Basis basis = camera_basis(camera.target + back, camera.target, camera.up);

  // For a corner at (x, y) across the view and z towards the eye (relative to the target), the
  // eye distance d must satisfy |x| <= (d - z) tan(half_fov_x) and the same for y; the
  // largest such d over the eight corners is the tightest fit.
  const float tan_y = std::tan(0.5f * fov_y_deg * kPi / 180.0f) / std::max(margin, 1.0f);
  const float tan_x = tan_y * std::max(aspect, 1e-3f);
  float distance = 0.0f;
  float radius = 0.5f * (max - min).norm();
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3f p((corner & 1) ? max.x() : min.x(), (corner & 2) ? max.y() : min.y(),
                            (corner & 4) ? max.z() : min.z());
    const Eigen::Vector3f rel = p - camera.target;
    const float x = std::abs(rel.dot(basis.right));
    const float y = std::abs(rel.dot(basis.up));
    const float z = rel.dot(back);
    distance = std::max({distance, z + x / tan_x, z + y / tan_y});
  }
  radius = std::max(radius, 1e-4f);
  distance = std::max(distance, 2.0f * radius);
  camera.eye = camera.target + back * distance;
  // Near plane just in front of the box, far plane past it with room for the ground plane,
  // which the renderer fades out at a few scene radii.
  camera.near_m = std::max(0.25f * (distance - radius), 1e-3f * distance);
  camera.far_m = distance + 8.0f * radius;
  return camera;
}

RenderCamera frame_scene(const RenderScene& scene, float aspect,
                         const Eigen::Vector3f& view_direction) {
  std::optional<Bounds3f> bounds = scene_bounds(scene, true);
  if (!bounds) bounds = scene_bounds(scene, false);
  if (!bounds) return scene.camera;
  return frame_bounds(bounds->min, bounds->max, aspect, view_direction, scene.camera.fov_y_deg);
}

}  // namespace acdr
