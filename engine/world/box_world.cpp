#include "engine/world/box_world.hpp"

namespace acdr {

WorldConfig make_box_world(const BoxWorldOptions& o) {
  WorldConfig c;
  const Vec3 lo(-0.5 * o.cavity_m.x(), -0.5 * o.cavity_m.y(), 0.0);
  const Vec3 hi(0.5 * o.cavity_m.x(), 0.5 * o.cavity_m.y(), o.cavity_m.z());
  c.ground.enabled = true;
  c.ground.height_m = -2e-3;
  c.box.enabled = true;
  c.box.inner_min_m = lo;
  c.box.inner_max_m = hi;
  c.nucleus.enabled = o.nucleus;
  c.nucleus.spacing_m = o.spacing_m;
  c.nucleus.materials.push_back(o.material);
  c.nucleus.blocks.push_back({lo, Vec3(hi.x(), hi.y(), o.fill_height_m), 0});
  c.instrument.enabled = true;
  c.instrument.blade_size_m = o.blade_m;
  c.instrument.shaft_length_m = o.shaft_length_m;
  c.instrument_start.position = Vec3(0, 0, o.grip_height_m);
  c.removal.min_m = Vec3(lo.x(), lo.y(), -1e-3);
  c.removal.max_m = hi;
  return c;
}

}  // namespace acdr
