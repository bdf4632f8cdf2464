// Which points a particle block fills.
#include "engine/nucleus/nucleus_config.hpp"

namespace acdr {

bool ParticleBlockConfig::contains(const Vec3& p) const {
  if ((p.array() < min_m.array()).any() || (p.array() > max_m.array()).any()) return false;
  if (has_cutout && (p.array() >= cutout_min_m.array()).all() &&
      (p.array() <= cutout_max_m.array()).all()) {
    return false;
  }
  if (shape == BlockShape::kBox) return true;
  const int ia = axis == 0 ? 1 : 0, ib = axis == 2 ? 1 : 2;
  const double u = p[ia] - center_m[ia], v = p[ib] - center_m[ib];
  auto inside = [&](double a, double b) {
    return a > 0.0 && b > 0.0 && (u / a) * (u / a) + (v / b) * (v / b) <= 1.0;
  };
  return inside(semi_a_m, semi_b_m) && !inside(hole_a_m, hole_b_m);
}

}  // namespace acdr
