// Colliders of the ground and the open box.
#include "engine/rigid/static_scene.hpp"

namespace acdr {

std::vector<Collider> build_static_colliders(const GroundConfig& ground, const OpenBoxConfig& box) {
  std::vector<Collider> out;
  if (ground.enabled) {
    Collider g;
    g.kind = ColliderKind::kHalfSpace;
    g.pose.position = Vec3(0, 0, ground.height_m);
    out.push_back(g);
  }
  if (box.enabled) {
    // Five wall actors (seed Sec. IV.B): floor and four sides around the inner cavity.
    const auto walls = open_box_walls(box.inner_min_m, box.inner_max_m, box.wall_thickness_m);
    out.insert(out.end(), walls.begin(), walls.end());
  }
  return out;
}

std::vector<Collider> open_box_walls(const Vec3& lo, const Vec3& hi, double t) {
  std::vector<Collider> out;
  out.reserve(5);
  auto wall = [&](const Vec3& min, const Vec3& max) {
    Collider c;
    c.kind = ColliderKind::kBox;
    c.pose.position = 0.5 * (min + max);
    c.half_extents_m = 0.5 * (max - min);
    out.push_back(c);
  };
  wall(Vec3(lo.x() - t, lo.y() - t, lo.z() - t), Vec3(hi.x() + t, hi.y() + t, lo.z()));  // floor
  wall(Vec3(lo.x() - t, lo.y() - t, lo.z()), Vec3(lo.x(), hi.y() + t, hi.z()));  // -x
  wall(Vec3(hi.x(), lo.y() - t, lo.z()), Vec3(hi.x() + t, hi.y() + t, hi.z()));  // +x
  wall(Vec3(lo.x(), lo.y() - t, lo.z()), Vec3(hi.x(), lo.y(), hi.z()));          // -y
  wall(Vec3(lo.x(), hi.y(), lo.z()), Vec3(hi.x(), hi.y() + t, hi.z()));          // +y
  return out;
}

}  // namespace acdr
