// A World drawn offscreen: the picture is not blank, the nucleus shows in its colour, and
// removed material is coloured apart.
#include "ui/scene_snapshot.hpp"

#include <gtest/gtest.h>

#include "engine/world/box_world.hpp"
#include "ui/offscreen_render.hpp"

namespace acdr {
namespace {

WorldConfig box_world() {
  BoxWorldOptions o;
  o.cavity_m = Vec3(16e-3, 12e-3, 8e-3);
  o.blade_m = Vec3(10e-3, 6e-3, 2e-3);
  o.shaft_length_m = 0.08;
  o.grip_height_m = 0.1;
  WorldConfig c = make_box_world(o);
  // Only the left half of the block counts as in place: the right half shows as removed.
  c.removal.max_m.x() = 0.0;
  return c;
}

/// Pixels whose colour is close in hue to `rgb` (lighting scales brightness).
int count_hue(const std::vector<std::uint8_t>& image, const Eigen::Vector3f& rgb) {
  int n = 0;
  const Eigen::Vector3f want = rgb.normalized();
  for (std::size_t i = 0; i + 2 < image.size(); i += 3) {
    const Eigen::Vector3f c(image[i], image[i + 1], image[i + 2]);
    if (c.norm() < 60.0f) continue;  // too dark to judge
    if (c.normalized().dot(want) > 0.995f) ++n;
  }
  return n;
}

TEST(SceneSnapshot, DrawsTheBoxNucleusAndRemovedMaterialAsSurfaces) {
  const World world(box_world());
  const SceneStyle style;
  const RenderScene scene = snapshot_world(world, 640.0f / 400.0f, style);
  EXPECT_TRUE(scene.particles.positions.empty());
  // The nucleus in place and the removed material, as wet gel, then the five walls, blade and
  // shaft (opaque before translucent).
  ASSERT_EQ(scene.meshes.size(), 2u + 5u + 2u);
  int gel = 0;
  for (const RenderMesh& m : scene.meshes) {
    if (m.finish != SurfaceFinish::kWetGel) continue;
    ++gel;
    EXPECT_FALSE(m.indices.empty());
    EXPECT_EQ(m.normals.size(), m.vertices.size());
    EXPECT_TRUE(m.rgba == style.nucleus || m.rgba == style.removed);
  }
  EXPECT_EQ(gel, 2);

  std::vector<std::uint8_t> rgb;
  std::string error;
  ASSERT_TRUE(render_to_rgb(scene, 640, 400, &rgb, &error)) << error;
  ASSERT_EQ(rgb.size(), 640u * 400u * 3u);
  // Not blank: many distinct colours.
  int differing = 0;
  for (std::size_t i = 3; i < rgb.size(); i += 3)
    differing += rgb[i] != rgb[0] || rgb[i + 1] != rgb[1] || rgb[i + 2] != rgb[2];
  EXPECT_GT(differing, 640 * 400 / 4);
  const int nucleus = count_hue(rgb, style.nucleus.head<3>());
  const int removed = count_hue(rgb, style.removed.head<3>());
  EXPECT_GT(nucleus, 500) << "nucleus-coloured pixels";
  EXPECT_GT(removed, 500) << "removed-material pixels";
}

TEST(SceneSnapshot, BeadsShowTheParticlesForDebugging) {
  const World world(box_world());
  SnapshotOptions beads;
  beads.drawing = MaterialDrawing::kBeads;
  const RenderScene scene = snapshot_world(world, 640.0f / 400.0f, {}, beads);
  EXPECT_EQ(scene.particles.positions.size(), 16u * 12u * 4u);
  EXPECT_EQ(scene.meshes.size(), 5u + 2u);  // five walls, blade and shaft
  // The same camera either way: the framing follows the particles, not how they are drawn.
  const RenderScene surfaces = snapshot_world(world, 640.0f / 400.0f);
  EXPECT_EQ(scene.camera.eye, surfaces.camera.eye);
  EXPECT_EQ(scene.camera.target, surfaces.camera.target);
}

}  // namespace
}  // namespace acdr
