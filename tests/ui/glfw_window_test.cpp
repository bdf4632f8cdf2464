// Tests of ui/glfw_window: the same scene renderer and ImGui renderer draw into a GLFW window as
// offscreen, and an OSMesa picture in the same process stays correct. Needs a display (run
// under xvfb-run); skipped without one.
#include "ui/glfw_window.hpp"

#include <cstdlib>

#include <gtest/gtest.h>
#include <imgui.h>

#include "tests/ui/image_probe.hpp"
#include "ui/imgui_gl_renderer.hpp"
#include "ui/offscreen_render.hpp"
#include "ui/render_camera.hpp"
#include "ui/sample_scene.hpp"
#include "ui/scene_renderer.hpp"

namespace acdr {
namespace {

bool has_display() {
  const char* display = std::getenv("DISPLAY");
  return display && *display;
}

TEST(GlfwWindow, DrawsTheSceneAndImGuiLikeOffscreen) {
  if (!has_display()) GTEST_SKIP() << "no DISPLAY (run under xvfb-run to test windows)";
  GlfwWindowOptions options;
  options.width = 640;
  options.height = 360;
  options.visible = false;
  options.vsync = false;
  std::string error;
  auto window = GlfwWindow::create(options, &error);
  ASSERT_TRUE(window) << error;
  EXPECT_TRUE(window->gl().missing().empty());
  int w = 0, h = 0;
  window->framebuffer_size(&w, &h);
  ASSERT_GT(w, 0);

  auto renderer = SceneRenderer::create(window->gl(), &error);
  ASSERT_TRUE(renderer) << error;
  ImGuiContext* imgui = ImGui::CreateContext();
  ImGui::SetCurrentContext(imgui);
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::GetIO().DisplaySize = ImVec2(float(w), float(h));
  auto imgui_renderer = ImGuiGlRenderer::create(window->gl(), &error);
  ASSERT_TRUE(imgui_renderer) << error;

  const RenderScene scene = make_sample_scene(5000, float(w) / h);
  for (int frame = 0; frame < 3; ++frame) {  // ImGui windows settle over a few frames
    ImGui::NewFrame();
    ImGui::SetNextWindowPos(ImVec2(10, 10));
    ImGui::SetNextWindowSize(ImVec2(220, 80));
    ImGui::Begin("Status");
    ImGui::TextUnformatted("WWWWWWWWWWWWWWWWWW");
    ImGui::End();
    ImGui::Render();
    const RenderStats stats = renderer->render(scene, w, h);
    EXPECT_EQ(stats.gl_error, "");
    imgui_renderer->render(ImGui::GetDrawData(), w, h);
    if (frame < 2) window->swap_buffers();
  }
  test::Image image{w, h, window->read_back_buffer_rgb()};
  const auto px = project_to_pixel(scene.camera, w, h,
                                   {-0.012f, 0.0f, scene.particles.positions.back().z()});
  ASSERT_TRUE(px);
  EXPECT_GT(image.fraction_in_window(*px, 2, test::is_nucleus_yellow), 0.6);
  int bright = 0;
  for (int x = 14; x < 220; ++x) {
    for (int y = 34; y < 60; ++y) {
      const test::Rgb c = image.at(x, y);
      bright += c.r > 150 && c.g > 150 && c.b > 150;
    }
  }
  EXPECT_GT(bright, 100);  // the text line

  imgui_renderer.reset();
  ImGui::DestroyContext(imgui);
  renderer.reset();

  // OSMesa in the same process, after GLFW has loaded libGL privately: still not black.
  std::vector<std::uint8_t> rgb;
  ASSERT_TRUE(render_to_rgb(scene, 320, 180, &rgb, &error)) << error;
  test::Image offscreen{320, 180, rgb};
  const auto opx = project_to_pixel(scene.camera, 320, 180,
                                    {-0.012f, 0.0f, scene.particles.positions.back().z()});
  EXPECT_GT(offscreen.fraction_in_window(*opx, 1, test::is_nucleus_yellow), 0.5);
}

}  // namespace
}  // namespace acdr
