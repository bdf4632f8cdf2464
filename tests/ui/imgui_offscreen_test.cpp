// Tests of ui/imgui_offscreen (and through it ui/imgui_gl_renderer): ImGui windows drawn over the
// 3D scene offscreen, with their text legible where the window is, the scene intact elsewhere,
// and the caller's ImGui context left alone.
#include "ui/imgui_offscreen.hpp"

#include <unistd.h>

#include <filesystem>

#include <gtest/gtest.h>
#include <imgui.h>
#include <stb_image.h>

#include "tests/ui/image_probe.hpp"
#include "ui/render_camera.hpp"
#include "ui/sample_scene.hpp"

namespace acdr {
namespace {

using test::Image;
using test::Rgb;

constexpr int kWidth = 640;
constexpr int kHeight = 360;

// A fixed window in the top-left corner: position and size in pixels.
constexpr float kWinX = 12, kWinY = 12, kWinW = 260, kWinH = 110;

void status_window(const char* text) {
  ImGui::SetNextWindowPos(ImVec2(kWinX, kWinY));
  ImGui::SetNextWindowSize(ImVec2(kWinW, kWinH));
  ImGui::Begin("Status", nullptr, ImGuiWindowFlags_NoCollapse);
  if (text) {
    ImGui::TextUnformatted(text);
    ImGui::TextUnformatted(text);
  }
  ImGui::End();
}

// Fraction of bright, grey pixels (ImGui's default text is white-ish) in a rectangle.
double text_fraction(const Image& image, int x0, int y0, int x1, int y1) {
  int hits = 0, total = 0;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const Rgb c = image.at(x, y);
      ++total;
      hits += c.r > 150 && c.g > 150 && c.b > 150;
    }
  }
  return static_cast<double>(hits) / total;
}

class ImGuiOffscreenTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    std::string error;
    ui_ = ImGuiOffscreen::create(kWidth, kHeight, &error).release();
    ASSERT_NE(ui_, nullptr) << error;
  }
  static void TearDownTestSuite() {
    delete ui_;
    ui_ = nullptr;
  }
  Image render(const RenderScene* scene, const ImGuiDrawFunction& draw) {
    Image image{kWidth, kHeight, {}};
    std::string error;
    EXPECT_TRUE(ui_->render(scene, draw, &image.rgb, &error)) << error;
    return image;
  }
  static ImGuiOffscreen* ui_;
};
ImGuiOffscreen* ImGuiOffscreenTest::ui_ = nullptr;

TEST_F(ImGuiOffscreenTest, TextAppearsInTheWindowOverTheScene) {
  const RenderScene scene = make_sample_scene(2000, float(kWidth) / kHeight);
  const Image with_text = render(&scene, [] { status_window("Nucleus removed: 42 %  WWWWWW"); });
  const Image no_text = render(&scene, [] { status_window(nullptr); });
  // The window body below the title bar holds the two text lines.
  const int bx0 = int(kWinX) + 4, bx1 = int(kWinX + kWinW) - 4;
  const int by0 = int(kWinY) + 24, by1 = int(kWinY + kWinH) - 4;
  EXPECT_GT(text_fraction(with_text, bx0, by0, bx1, by1), 0.03);
  EXPECT_LT(text_fraction(no_text, bx0, by0, bx1, by1), 0.005);
  // The window background is ImGui's dark grey, not the scene: inside the body, away from text.
  const Rgb body = no_text.at(int(kWinX + kWinW / 2), int(kWinY + kWinH - 10));
  EXPECT_LT(std::max({body.r, body.g, body.b}), 40);
  // The title bar shows the title in light text.
  EXPECT_GT(text_fraction(with_text, int(kWinX) + 4, int(kWinY) + 2, int(kWinX) + 80,
                          int(kWinY) + 20),
            0.03);
  // Away from the window the scene is untouched: the particles on the block's top.
  const auto px = project_to_pixel(scene.camera, kWidth, kHeight,
                                   {-0.012f, 0.0f, scene.particles.positions.back().z()});
  ASSERT_TRUE(px);
  EXPECT_GT(with_text.fraction_in_window(*px, 2, test::is_nucleus_yellow), 0.6);
}

TEST_F(ImGuiOffscreenTest, WidgetColoursShow) {
  // A progress bar fills with ImGui's histogram colour (orange-yellow) in proportion.
  const Image image = render(nullptr, [] {
    ImGui::SetNextWindowPos(ImVec2(20, 20));
    ImGui::SetNextWindowSize(ImVec2(400, 80));
    ImGui::Begin("Progress");
    ImGui::ProgressBar(0.5f, ImVec2(360, 20), "");
    ImGui::End();
  });
  int filled = 0, empty = 0;
  for (int x = 40; x < 380; ++x) {
    // The bar sits on the first line of the window's content, ~ 30 px below the title bar top.
    bool found = false;
    for (int y = 45; y < 70 && !found; ++y) {
      const Rgb c = image.at(x, y);
      found = c.r > 180 && c.g > 120 && c.b < 60;
    }
    (found ? filled : empty)++;
  }
  EXPECT_NEAR(static_cast<double>(filled) / (filled + empty), 0.5, 0.1);
}

TEST_F(ImGuiOffscreenTest, WithoutASceneTheBackgroundIsTheClearColour) {
  const Image image = render(nullptr, [] { status_window("x"); });
  const Rgb corner = image.at(kWidth - 3, kHeight - 3);
  const ImGuiOffscreenOptions defaults;
  EXPECT_NEAR(corner.r, defaults.clear_rgb.x() * 255, 2);
  EXPECT_NEAR(corner.b, defaults.clear_rgb.z() * 255, 2);
}

TEST_F(ImGuiOffscreenTest, LeavesTheCallersImGuiContextCurrent) {
  ImGuiContext* mine = ImGui::CreateContext();
  ImGui::SetCurrentContext(mine);
  render(nullptr, [] {
    ImGui::Begin("inside");
    ImGui::End();
  });
  EXPECT_EQ(ImGui::GetCurrentContext(), mine);
  EXPECT_NE(ui_->imgui_context(), mine);
  ImGui::DestroyContext(mine);
}

TEST(ImGuiOffscreen, WritesAPngAndRefusesAMissingFont) {
  const std::string path =
      (std::filesystem::temp_directory_path() /
       ("acdr_imgui_offscreen_test_" + std::to_string(::getpid()) + ".png"))
          .string();
  std::string error;
  ASSERT_TRUE(render_imgui_to_png(nullptr, 200, 100, [] { status_window("hello"); }, path,
                                  &error))
      << error;
  int w = 0, h = 0, channels = 0;
  stbi_uc* decoded = stbi_load(path.c_str(), &w, &h, &channels, 0);
  ASSERT_NE(decoded, nullptr);
  EXPECT_EQ(w, 200);
  EXPECT_EQ(h, 100);
  EXPECT_EQ(channels, 3);
  stbi_image_free(decoded);
  std::filesystem::remove(path);

  ImGuiOffscreenOptions options;
  options.font_path = "/nonexistent/font.ttf";
  EXPECT_FALSE(ImGuiOffscreen::create(64, 64, &error, options));
  EXPECT_NE(error.find("/nonexistent/font.ttf"), std::string::npos) << error;
}

}  // namespace
}  // namespace acdr
