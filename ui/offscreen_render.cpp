// Offscreen rendering in one call.
#include "ui/offscreen_render.hpp"

#include "ui/png_writer.hpp"

namespace acdr {

std::unique_ptr<OffscreenRenderer> OffscreenRenderer::create(int width, int height,
                                                             std::string* error, int samples) {
  std::unique_ptr<OffscreenRenderer> r(new OffscreenRenderer());
  r->context_ = OffscreenContext::create(width, height, samples, error);
  if (!r->context_) return nullptr;
  r->renderer_ = SceneRenderer::create(r->context_->gl(), error);
  if (!r->renderer_) return nullptr;
  return r;
}

bool OffscreenRenderer::render(const RenderScene& scene, std::vector<std::uint8_t>* rgb,
                               std::string* error, RenderStats* stats,
                               const OverlayCallback& overlay) {
  if (!context_->make_current(error)) return false;
  context_->begin_frame();
  RenderStats frame_stats = renderer_->render(scene, width(), height());
  if (stats) *stats = frame_stats;
  if (!frame_stats.gl_error.empty()) {
    if (error) *error = frame_stats.gl_error;
    return false;
  }
  if (overlay && !overlay(context_->gl(), width(), height(), error)) return false;
  if (!context_->end_frame(error)) return false;
  if (rgb) *rgb = context_->rgb_top_down();
  return true;
}

bool render_to_rgb(const RenderScene& scene, int width, int height,
                   std::vector<std::uint8_t>* rgb, std::string* error) {
  std::unique_ptr<OffscreenRenderer> renderer = OffscreenRenderer::create(width, height, error);
  if (!renderer) return false;
  return renderer->render(scene, rgb, error);
}

bool render_to_png(const RenderScene& scene, int width, int height, const std::string& path,
                   std::string* error) {
  std::vector<std::uint8_t> rgb;
  if (!render_to_rgb(scene, width, height, &rgb, error)) return false;
  return write_png_rgb(path, width, height, rgb, error);
}

}  // namespace acdr
