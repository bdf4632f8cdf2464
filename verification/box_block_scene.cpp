// The box module's nucleus scene (see the header).
#include "verification/box_block_scene.hpp"

#include "engine/rigid/static_scene.hpp"

namespace acdr {

BoxBlockScene make_box_block_scene(double spacing_m, const MaterialConfig& material) {
  BoxBlockScene s;
  s.nucleus.enabled = true;
  s.nucleus.spacing_m = spacing_m;
  s.nucleus.materials.push_back(material);
  s.nucleus.blocks.push_back(ParticleBlockConfig{Vec3(0, 0, 0), Vec3(0.03, 0.02, 0.008), 0});
  s.statics = open_box_walls(Vec3(0, 0, 0), Vec3(0.03, 0.02, 0.012), 2.0e-3);
  s.blade.kind = ColliderKind::kBox;
  s.blade.half_extents_m = Vec3(4.0e-3, 2.0e-3, 5.0e-3);
  s.blade.pose.position = Vec3(0.015, 0.010, 0.0135);
  s.blade.body = 0;
  return s;
}

}  // namespace acdr
