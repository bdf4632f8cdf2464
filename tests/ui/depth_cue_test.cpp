// Tests of ui/depth_cue: the tip's depth against the disc's front and back, in millimetres and
// in words, above, in and beyond the disc; and the C4-C5 module's reference from its anatomy.
#include "ui/depth_cue.hpp"

#include <gtest/gtest.h>

#include "scenarios/scenario_loader.hpp"

namespace acdr {
namespace {

DepthReference disc() {
  DepthReference r;
  r.valid = true;
  r.surface_z_m = 4.5e-3;
  r.floor_z_m = -5.6e-3;
  r.surface_name = "front of the disc";
  r.floor_name = "back of the disc (PLL, spinal cord)";
  return r;
}

TEST(DepthCue, DepthAboveInAndBeyondTheDisc) {
  Frame f;
  f.tip_m = Vec3(0.001, 0.0, 7.5e-3);  // 3 mm above the front
  DepthCue cue = make_depth_cue(disc(), f);
  EXPECT_NEAR(cue.depth_m, -3e-3, 1e-12);
  EXPECT_EQ(depth_text(cue), "3.0 mm above the front of the disc");
  f.tip_m.z() = 0.3e-3;  // 4.2 mm in, 5.9 mm to the back
  cue = make_depth_cue(disc(), f);
  EXPECT_NEAR(cue.depth_m, 4.2e-3, 1e-12);
  EXPECT_NEAR(cue.to_floor_m, 5.9e-3, 1e-12);
  EXPECT_EQ(depth_text(cue), "4.2 mm in, 5.9 mm to the back of the disc (PLL, spinal cord)");
  f.tip_m.z() = -6.6e-3;  // 1 mm beyond the back
  cue = make_depth_cue(disc(), f);
  EXPECT_EQ(depth_text(cue), "11.1 mm in: 1.0 mm beyond the back of the disc (PLL, spinal cord)");
  DepthReference none;
  EXPECT_EQ(depth_text(make_depth_cue(none, f)), "");
}

TEST(DepthCue, TheC4C5ModuleMeasuresFromTheDiscsFrontToTheBodiesBackWall) {
  LoadResult loaded =
      load_scenario_file(std::string(ACDR_SOURCE_DIR) + "/scenarios/modules/02_c4c5_healthy.json");
  ASSERT_TRUE(loaded.ok());
  World world(loaded.model->world);
  WorldState state;
  capture_world_state(world, state);
  const DepthReference r = depth_reference(world, state);
  ASSERT_TRUE(r.valid);
  // The disc's material starts where the trainee meets it through the window cut in the
  // annulus's front: the nucleus's front (its centre at z = -0.25 mm plus its 4.68 mm semi-axis:
  // 4.43 mm), to within the 1 mm lattice; the back is the vertebral bodies' back wall, behind
  // the nucleus (z >= -3.5 mm).
  EXPECT_NEAR(r.surface_z_m, 4.43e-3, 1.0e-3);
  EXPECT_LT(r.floor_z_m, -3.5e-3);
  EXPECT_EQ(r.floor_name, "back of the disc (PLL, spinal cord)");
}

}  // namespace
}  // namespace acdr
