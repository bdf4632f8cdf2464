// Tests of ui/scene_renderer on the sample scene (ui/sample_scene.hpp), rendered offscreen: each
// part appears in its colour where the camera projects it, depth and blending order hold, and
// the particle paths (point sprites, quads for close-ups) both draw.
#include "ui/scene_renderer.hpp"

#include <gtest/gtest.h>

#include "tests/ui/image_probe.hpp"
#include "ui/mesh_primitives.hpp"
#include "ui/offscreen_render.hpp"
#include "ui/render_camera.hpp"
#include "ui/sample_scene.hpp"

namespace acdr {
namespace {

using test::Image;
using test::Rgb;

constexpr int kWidth = 640;
constexpr int kHeight = 360;

class SceneRendererTest : public ::testing::Test {
 protected:
  // One context and renderer for the suite: shader compilation on llvmpipe costs ~0.5 s.
  static void SetUpTestSuite() {
    std::string error;
    renderer_ = OffscreenRenderer::create(kWidth, kHeight, &error, 4).release();
    ASSERT_NE(renderer_, nullptr) << error;
  }
  static void TearDownTestSuite() {
    delete renderer_;
    renderer_ = nullptr;
  }

  Image render(const RenderScene& scene, RenderStats* stats = nullptr) {
    Image image{kWidth, kHeight, {}};
    std::string error;
    RenderStats local;
    EXPECT_TRUE(renderer_->render(scene, &image.rgb, &error, &local)) << error;
    EXPECT_EQ(local.gl_error, "");
    if (stats) *stats = local;
    return image;
  }

  Eigen::Vector2f pixel_of(const RenderScene& scene, const Eigen::Vector3f& world) {
    const auto p = project_to_pixel(scene.camera, kWidth, kHeight, world);
    EXPECT_TRUE(p);
    return p.value_or(Eigen::Vector2f::Zero());
  }

  static OffscreenRenderer* renderer_;
  const SampleSceneLayout layout_;
};
OffscreenRenderer* SceneRendererTest::renderer_ = nullptr;

TEST_F(SceneRendererTest, TheImageIsNotBlank) {
  const RenderScene scene = make_sample_scene(5000, float(kWidth) / kHeight);
  RenderStats stats;
  const Image image = render(scene, &stats);
  const Rgb bg{static_cast<int>(std::lround(scene.background.x() * 255)),
               static_cast<int>(std::lround(scene.background.y() * 255)),
               static_cast<int>(std::lround(scene.background.z() * 255))};
  const double drawn = image.fraction([&](const Rgb& c) {
    return std::abs(c.r - bg.r) + std::abs(c.g - bg.g) + std::abs(c.b - bg.b) > 12;
  });
  EXPECT_GT(drawn, 0.3);
  EXPECT_EQ(stats.opaque_meshes, 6);
  EXPECT_EQ(stats.translucent_meshes, 1);
  EXPECT_EQ(stats.particles, 5000);
  EXPECT_TRUE(stats.particles_as_points);
  // The corner above the far end of the scene shows the background (the ground fades out).
  const Rgb corner = image.at(2, 2);
  EXPECT_NEAR(corner.r, bg.r, 3);
  EXPECT_NEAR(corner.b, bg.b, 3);
}

TEST_F(SceneRendererTest, ParticlesAppearOnTopOfTheBlock) {
  const RenderScene scene = make_sample_scene(5000, float(kWidth) / kHeight);
  const Image image = render(scene);
  // A spot on the block's top, clear of the instrument and the zone.
  const Eigen::Vector3f top(-0.012f, 0.0f, scene.particles.positions.back().z());
  const Eigen::Vector2f px = pixel_of(scene, top);
  EXPECT_GT(image.fraction_in_window(px, 3, test::is_nucleus_yellow), 0.6)
      << "at " << px.transpose();
  // Hiding every particle (alpha 0) removes them.
  RenderScene hidden = scene;
  for (Eigen::Vector4f& c : hidden.particles.colors) c.w() = 0.0f;
  RenderStats stats;
  const Image without = render(hidden, &stats);
  EXPECT_EQ(stats.particles, 0);
  EXPECT_LT(without.fraction_in_window(px, 3, test::is_nucleus_yellow), 0.1);
}

TEST_F(SceneRendererTest, TheFrontWallHidesTheParticlesBehindIt) {
  const RenderScene scene = make_sample_scene(5000, float(kWidth) / kHeight);
  const Image image = render(scene);
  // A particle low at the front (-y side, facing the camera), below the wall's top edge.
  const Eigen::Vector3f behind_wall(0.0f, layout_.block_min.y() + 0.001f, 0.002f);
  const Eigen::Vector2f px = pixel_of(scene, behind_wall);
  EXPECT_GT(image.fraction_in_window(px, 2, test::is_wall_blue), 0.9) << px.transpose();
  EXPECT_EQ(image.fraction_in_window(px, 2, test::is_nucleus_yellow), 0.0);
}

TEST_F(SceneRendererTest, TheInstrumentIsSteelColoured) {
  const RenderScene scene = make_sample_scene(5000, float(kWidth) / kHeight);
  const Image image = render(scene);
  const Eigen::Vector2f px = pixel_of(scene, layout_.blade_center);
  EXPECT_GT(image.fraction_in_window(px, 3, test::is_steel), 0.8) << px.transpose();
  // And it is the instrument that makes it so: moved away, the steel goes.
  RenderScene moved = scene;
  moved.meshes[5].pose.translation() += Eigen::Vector3f(0.0f, 0.0f, 0.5f);
  const Image without = render(moved);
  EXPECT_LT(without.fraction_in_window(px, 3, test::is_steel), 0.2);
}

TEST_F(SceneRendererTest, TheDangerZoneBlendsOverWhatIsBehindIt) {
  RenderScene scene = make_sample_scene(5000, float(kWidth) / kHeight);
  const Eigen::Vector2f px = pixel_of(scene, layout_.zone_center);
  const Image translucent = render(scene);
  RenderScene opaque = scene;
  opaque.meshes[6].rgba.w() = 1.0f;
  const Image solid = render(opaque);
  RenderScene none = scene;
  none.meshes.pop_back();
  const Image without = render(none);
  const Rgb t = translucent.at(px), s = solid.at(px), n = without.at(px);
  // Redder than the scene behind it...
  EXPECT_GT(t.r - std::max(t.g, t.b), n.r - std::max(n.g, n.b) + 40)
      << "zone " << t.r << "," << t.g << "," << t.b << " behind " << n.r << "," << n.g << ","
      << n.b;
  // ...but not the opaque zone colour: what lies behind still shows through.
  EXPECT_GT(std::abs(t.g - s.g) + std::abs(t.b - s.b), 20)
      << "translucent " << t.r << "," << t.g << "," << t.b << " opaque " << s.r << "," << s.g
      << "," << s.b;
}

TEST_F(SceneRendererTest, TranslucentMeshesDoNotHideEachOtherWhateverTheirOrder) {
  // Two translucent spheres one behind the other; the result must not depend on list order.
  RenderScene scene;
  scene.ground.visible = false;
  scene.meshes.push_back(make_sphere({0, 0, 0}, 0.01f, {0.1f, 0.2f, 0.9f, 0.5f}));
  scene.meshes.push_back(make_sphere({0.0f, 0.03f, 0.0f}, 0.01f, {0.9f, 0.1f, 0.1f, 0.5f}));
  scene.camera.eye = {0.0f, -0.1f, 0.0f};
  scene.camera.target = {0, 0, 0};
  const Image ab = render(scene);
  std::swap(scene.meshes[0], scene.meshes[1]);
  const Image ba = render(scene);
  const Eigen::Vector2f center(kWidth / 2.0f, kHeight / 2.0f);
  const Rgb x = ab.at(center), y = ba.at(center);
  EXPECT_NEAR(x.r, y.r, 2);
  EXPECT_NEAR(x.g, y.g, 2);
  EXPECT_NEAR(x.b, y.b, 2);
  // The near sphere is blue and drawn last: blue dominates, red shows through.
  EXPECT_GT(x.b, x.r);
  EXPECT_GT(x.r, 40);
}

TEST_F(SceneRendererTest, CloseUpsDrawParticlesAsQuads) {
  // A few big spheres right in front of the camera exceed the point size limit.
  const float r = 0.003f;
  RenderScene scene;
  scene.ground.visible = false;
  scene.particles.positions = {{0, 0, 0}, {0.008f, 0, 0}};
  scene.particles.colors = {{0.96f, 0.76f, 0.28f, 1.0f}, {0.96f, 0.76f, 0.28f, 1.0f}};
  scene.particles.radius_m = r;
  scene.camera.eye = {0.0f, -0.009f, 0.001f};
  scene.camera.target = {0.0f, 0.0f, 0.0f};
  scene.camera.near_m = 1e-4f;
  RenderStats stats;
  const Image image = render(scene, &stats);
  EXPECT_FALSE(stats.particles_as_points);
  const Eigen::Vector2f px = pixel_of(scene, Eigen::Vector3f::Zero());
  EXPECT_GT(image.fraction_in_window(px, 30, test::is_nucleus_yellow), 0.95);
  // Shaded as a sphere: lit from the upper left, the upper-left side is brighter. The points
  // lie on the sphere's near half.
  const Rgb upper_left = image.at(pixel_of(scene, r * Eigen::Vector3f(-0.5f, -0.7f, 0.5f)));
  const Rgb lower_right = image.at(pixel_of(scene, r * Eigen::Vector3f(0.5f, -0.7f, -0.5f)));
  EXPECT_GT(upper_left.r + upper_left.g, lower_right.r + lower_right.g + 40);
}

TEST_F(SceneRendererTest, TheInstrumentCastsAShadowOnTheParticles) {
  RenderScene scene = make_sample_scene(5000, float(kWidth) / kHeight);
  // Where the key light's ray through the blade's centre meets the top of the particles.
  const float top = scene.particles.positions.back().z();
  const Eigen::Vector3f to_light = key_light_direction(scene.camera);
  ASSERT_GT(to_light.z(), 0.1f);
  const Eigen::Vector3f c = layout_.blade_center;
  const Eigen::Vector3f shadow_spot = c - to_light * ((c.z() - top) / to_light.z());
  ASSERT_TRUE((shadow_spot.head<2>().array() > layout_.block_min.head<2>().array()).all() &&
              (shadow_spot.head<2>().array() < layout_.block_max.head<2>().array()).all())
      << "the shadow must fall on the block for this test: " << shadow_spot.transpose();
  const Eigen::Vector2f px = pixel_of(scene, shadow_spot);
  RenderStats stats;
  const Image lit = [&] {
    RenderScene no_shadows = scene;
    no_shadows.shadows.enabled = false;
    return render(no_shadows, &stats);
  }();
  EXPECT_FALSE(stats.shadows);
  const Image shaded = render(scene, &stats);
  EXPECT_TRUE(stats.shadows);
  auto brightness = [](const Image& image, const Eigen::Vector2f& p) {
    int sum = 0;
    for (int dy = -2; dy <= 2; ++dy) {
      for (int dx = -2; dx <= 2; ++dx) {
        const Rgb c = image.at(int(p.x()) + dx, int(p.y()) + dy);
        sum += c.r + c.g + c.b;
      }
    }
    return sum / 25.0;
  };
  EXPECT_LT(brightness(shaded, px), 0.8 * brightness(lit, px)) << "at " << px.transpose();
  // Particles in the open keep their light (within what their neighbours' shadows take).
  const Eigen::Vector2f open = pixel_of(scene, {-0.014f, 0.006f, top});
  EXPECT_GT(brightness(shaded, open), 0.8 * brightness(lit, open));
}

TEST_F(SceneRendererTest, CachesMeshesWithAGeometryId) {
  const RenderScene scene = make_sample_scene(100, float(kWidth) / kHeight);
  render(scene);
  SceneRenderer& r = renderer_->scene_renderer();
  EXPECT_GE(r.cached_geometry_count(), 7u);  // every sample mesh has an id
  r.forget_geometry(1006);
  EXPECT_GE(r.cached_geometry_count(), 6u);
  r.clear_geometry_cache();
  EXPECT_EQ(r.cached_geometry_count(), 0u);
  // Rendering again re-uploads and gives the same picture.
  const Image a = render(scene);
  const Image b = render(scene);
  EXPECT_EQ(a.rgb, b.rgb);
}

TEST_F(SceneRendererTest, SkipsAMeshWithBadIndicesWithoutAGlError) {
  RenderScene scene = make_sample_scene(100, float(kWidth) / kHeight);
  RenderMesh broken;
  broken.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  broken.indices = {0, 1, 7};
  scene.meshes.push_back(broken);
  RenderStats stats;
  render(scene, &stats);
  EXPECT_EQ(stats.skipped_meshes, 1);
  EXPECT_EQ(stats.opaque_meshes, 6);
}

TEST_F(SceneRendererTest, MeshesWithoutNormalsAreLitFlatAcrossCreases) {
  // A box whose normals the renderer must compute: each visible face is one flat tone, and
  // two faces differ (lit from different angles).
  RenderScene scene;
  scene.ground.visible = false;
  RenderMesh box = make_box({-0.01f, -0.01f, -0.01f}, {0.01f, 0.01f, 0.01f});
  box.normals.clear();
  scene.meshes.push_back(box);
  scene.camera = frame_bounds({-0.01f, -0.01f, -0.01f}, {0.01f, 0.01f, 0.01f},
                              float(kWidth) / kHeight);
  const Image image = render(scene);
  const Rgb top_a = image.at(pixel_of(scene, {-0.004f, -0.004f, 0.01f}));
  const Rgb top_b = image.at(pixel_of(scene, {0.004f, 0.004f, 0.01f}));
  const Rgb front = image.at(pixel_of(scene, {0.0f, -0.01f, 0.0f}));
  EXPECT_NEAR(top_a.g, top_b.g, 3);
  EXPECT_GT(std::abs(top_a.g - front.g), 10);
}

}  // namespace
}  // namespace acdr

namespace acdr {
namespace {

// Luminance spread over a square window of the image (standard deviation, 0..255).
double luminance_spread(const test::Image& image, const Eigen::Vector2f& at, int half) {
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int y = int(at.y()) - half; y <= int(at.y()) + half; ++y)
    for (int x = int(at.x()) - half; x <= int(at.x()) + half; ++x) {
      const test::Rgb c = image.at(x, y);
      const double l = 0.3 * c.r + 0.59 * c.g + 0.11 * c.b;
      sum += l, sum2 += l * l, ++n;
    }
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, sum2 / n - mean * mean));
}

TEST_F(SceneRendererTest, TheFibrousFinishDrawsLamellaeAndFibresTheOthersStaySmooth) {
  // A ring of annulus seen from its front, close up: 5 mm radius, the spine axis y vertical.
  RenderScene scene;
  scene.ground.visible = false;
  scene.shadows.enabled = false;
  RenderMesh ring = make_cylinder(Eigen::Vector3f(0, -2e-3f, 0), Eigen::Vector3f(0, 2e-3f, 0),
                                  5e-3f, Eigen::Vector4f(0.90f, 0.88f, 0.84f, 1.0f));
  scene.camera.eye = Eigen::Vector3f(0, 0, 0.02f);
  scene.camera.target = Eigen::Vector3f(0, 0, 5e-3f);
  scene.camera.up = Eigen::Vector3f::UnitY();
  scene.camera.fov_y_deg = 20.0f;
  scene.meshes = {ring};
  const Eigen::Vector2f front = pixel_of(scene, Eigen::Vector3f(0, 0, 5e-3f));
  const double plain = luminance_spread(render(scene), front, 12);
  scene.meshes[0].finish = SurfaceFinish::kFibrous;
  scene.meshes[0].pattern_origin = Eigen::Vector3f::Zero();
  scene.meshes[0].pattern_axis = Eigen::Vector3f::UnitY();
  const double fibrous = luminance_spread(render(scene), front, 12);
  scene.meshes[0].finish = SurfaceFinish::kWetGel;
  const double gel = luminance_spread(render(scene), front, 12);
  EXPECT_GT(fibrous, 3.0 * plain + 2.0) << "plain " << plain << ", fibrous " << fibrous;
  EXPECT_LT(gel, fibrous) << "gel " << gel;
}

}  // namespace
}  // namespace acdr
