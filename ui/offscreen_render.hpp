// One-call offscreen pictures of a RenderScene: for `acdr run --png`, `acdr render`, and tests.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ui/offscreen_context.hpp"
#include "ui/render_scene.hpp"
#include "ui/scene_renderer.hpp"

namespace acdr {

/// Draws on top of the scene before the frame is read back (e.g. an ImGui overlay). Called
/// with the context current and the frame's framebuffer bound; width, height in pixels.
using OverlayCallback = std::function<bool(const GlFunctions& gl, int width, int height,
                                           std::string* error)>;

/// An OSMesa context plus a scene renderer, kept together so that several frames (a series of
/// pictures, a benchmark) pay for context creation and shader compilation once.
class OffscreenRenderer {
 public:
  /// width x height pixels; `samples` = multisampling (4 by default, 1 = off).
  static std::unique_ptr<OffscreenRenderer> create(int width, int height, std::string* error,
                                                   int samples = 4);

  /// Renders `scene` (and `overlay`, when given) and returns the picture as RGB, top row first,
  /// width*height*3 bytes. Makes the context current on the calling thread.
  bool render(const RenderScene& scene, std::vector<std::uint8_t>* rgb, std::string* error,
              RenderStats* stats = nullptr, const OverlayCallback& overlay = nullptr);

  OffscreenContext& context() { return *context_; }
  SceneRenderer& scene_renderer() { return *renderer_; }
  int width() const { return context_->width(); }
  int height() const { return context_->height(); }

 private:
  OffscreenRenderer() = default;
  // Declared in this order so the renderer (whose GL objects live in the context) goes first.
  std::unique_ptr<OffscreenContext> context_;
  std::unique_ptr<SceneRenderer> renderer_;
};

/// Renders `scene` at width x height into `rgb` (RGB, top row first).
bool render_to_rgb(const RenderScene& scene, int width, int height,
                   std::vector<std::uint8_t>* rgb, std::string* error);

/// Renders `scene` at width x height and writes it to `path` as an RGB PNG.
bool render_to_png(const RenderScene& scene, int width, int height, const std::string& path,
                   std::string* error);

}  // namespace acdr
