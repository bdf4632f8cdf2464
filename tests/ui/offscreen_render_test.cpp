// Tests of ui/offscreen_render: the one-call PNG path writes a file that decodes to the
// rendered pixels.
#include "ui/offscreen_render.hpp"

#include <unistd.h>

#include <filesystem>

#include <gtest/gtest.h>
#include <stb_image.h>

#include "tests/ui/image_probe.hpp"
#include "ui/render_camera.hpp"
#include "ui/sample_scene.hpp"

namespace acdr {
namespace {

TEST(OffscreenRender, WritesAPngThatDecodesToTheRenderedScene) {
  const int w = 480, h = 270;
  const RenderScene scene = make_sample_scene(5000, float(w) / h);
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("acdr_offscreen_render_test_" + std::to_string(::getpid()) + ".png"))
                               .string();
  std::string error;
  ASSERT_TRUE(render_to_png(scene, w, h, path, &error)) << error;
  int dw = 0, dh = 0, channels = 0;
  stbi_uc* decoded = stbi_load(path.c_str(), &dw, &dh, &channels, 0);
  ASSERT_NE(decoded, nullptr) << stbi_failure_reason();
  EXPECT_EQ(dw, w);
  EXPECT_EQ(dh, h);
  EXPECT_EQ(channels, 3);
  test::Image image{w, h, std::vector<std::uint8_t>(decoded, decoded + w * h * 3)};
  stbi_image_free(decoded);
  std::filesystem::remove(path);

  // The same scene through render_to_rgb gives the same pixels (rendering is deterministic).
  std::vector<std::uint8_t> rgb;
  ASSERT_TRUE(render_to_rgb(scene, w, h, &rgb, &error)) << error;
  EXPECT_EQ(rgb, image.rgb);

  // And the picture shows the scene: the particle colour where the block's top projects.
  const SampleSceneLayout layout;
  const auto px = project_to_pixel(scene.camera, w, h,
                                   {-0.012f, 0.0f, scene.particles.positions.back().z()});
  ASSERT_TRUE(px);
  EXPECT_GT(image.fraction_in_window(*px, 2, test::is_nucleus_yellow), 0.6);
}

TEST(OffscreenRender, TheFirstFrameOfANewRendererIsLikeTheNext) {
  // Resources made on first use (shadow map, cached meshes) must not disturb that frame.
  const RenderScene scene = make_sample_scene(500, 1.5f);
  std::string error;
  auto renderer = OffscreenRenderer::create(192, 128, &error);
  ASSERT_TRUE(renderer) << error;
  std::vector<std::uint8_t> first, second;
  ASSERT_TRUE(renderer->render(scene, &first, &error)) << error;
  ASSERT_TRUE(renderer->render(scene, &second, &error)) << error;
  EXPECT_EQ(first, second);
}

TEST(OffscreenRender, ReportsABadImageSizeAndAnUnwritablePath) {
  const RenderScene scene = make_sample_scene(10);
  std::string error;
  EXPECT_FALSE(render_to_png(scene, 0, 100, "/tmp/never.png", &error));
  EXPECT_FALSE(error.empty());
  error.clear();
  EXPECT_FALSE(render_to_png(scene, 64, 64, "/nonexistent-dir/x.png", &error));
  EXPECT_NE(error.find("/nonexistent-dir/x.png"), std::string::npos) << error;
}

}  // namespace
}  // namespace acdr
