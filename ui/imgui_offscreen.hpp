// Dear ImGui drawn offscreen: one picture of caller-supplied ImGui windows, optionally over a
// 3D scene, through OSMesa. For `acdr dashboard --screenshot`, trainee-view screenshots and
// UI snapshot tests.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "ui/offscreen_render.hpp"
#include "ui/render_scene.hpp"

struct ImGuiContext;

namespace acdr {

class ImGuiGlRenderer;

struct ImGuiOffscreenOptions {
  /// A TrueType font file; empty: DejaVu Sans when installed (fonts-dejavu-core), else ImGui's
  /// built-in bitmap font.
  std::string font_path;
  float font_size_px = 16.0f;
  int samples = 4;  ///< multisampling of the 3D scene (1 = off)
  /// Background when no scene is drawn (sRGB).
  Eigen::Vector3f clear_rgb = Eigen::Vector3f(0.10f, 0.105f, 0.12f);
  /// ImGui frames run before the picture is taken; auto-sized windows need two to settle.
  int settle_frames = 3;
};

/// Builds the UI of one frame with ImGui calls (ImGui::Begin ... ImGui::End). Called once per
/// ImGui frame, i.e. `settle_frames` times per picture, with this object's ImGui context current.
using ImGuiDrawFunction = std::function<void()>;

/// Owns an OSMesa context, a scene renderer, its own ImGui context and an ImGui renderer.
/// The ImGui context is made current only inside render(); the caller's current ImGui context
/// (if any) is restored afterwards. ImGui's current-context pointer is one per process, so use
/// ImGui (this class included) from one thread at a time.
class ImGuiOffscreen {
 public:
  static std::unique_ptr<ImGuiOffscreen> create(int width, int height, std::string* error,
                                                const ImGuiOffscreenOptions& options = {});
  ~ImGuiOffscreen();
  ImGuiOffscreen(const ImGuiOffscreen&) = delete;
  ImGuiOffscreen& operator=(const ImGuiOffscreen&) = delete;

  /// Draws `scene` (or, when null, a plain background) and then the ImGui windows `draw_ui`
  /// builds, and returns the picture as RGB, top row first (width*height*3 bytes).
  bool render(const RenderScene* scene, const ImGuiDrawFunction& draw_ui,
              std::vector<std::uint8_t>* rgb, std::string* error);

  int width() const { return renderer_->width(); }
  int height() const { return renderer_->height(); }
  ImGuiContext* imgui_context() const { return imgui_context_; }
  /// The font in use: the TrueType file loaded, or "" for ImGui's built-in font.
  const std::string& font_path() const { return font_path_; }

 private:
  ImGuiOffscreen() = default;

  ImGuiOffscreenOptions options_;
  std::unique_ptr<OffscreenRenderer> renderer_;
  ImGuiContext* imgui_context_ = nullptr;
  std::unique_ptr<ImGuiGlRenderer> imgui_renderer_;
  std::string font_path_;
};

/// One picture of `draw_ui` over `scene` (may be null) at width x height, written as RGB PNG.
bool render_imgui_to_png(const RenderScene* scene, int width, int height,
                         const ImGuiDrawFunction& draw_ui, const std::string& path,
                         std::string* error, const ImGuiOffscreenOptions& options = {});

}  // namespace acdr
