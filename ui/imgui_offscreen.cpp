// ImGui frames rendered into an OSMesa buffer.
#include "ui/imgui_offscreen.hpp"

#include <algorithm>
#include <cfloat>
#include <fstream>

#include <imgui.h>

#include "ui/imgui_gl_renderer.hpp"
#include "ui/png_writer.hpp"

namespace acdr {

namespace {

const char* kDejaVuSans = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

bool readable(const std::string& path) { return std::ifstream(path).good(); }

// Makes `context` current for the lifetime of the guard, then restores the previous one.
class ImGuiContextScope {
 public:
  explicit ImGuiContextScope(ImGuiContext* context) : previous_(ImGui::GetCurrentContext()) {
    ImGui::SetCurrentContext(context);
  }
  ~ImGuiContextScope() { ImGui::SetCurrentContext(previous_); }
  ImGuiContextScope(const ImGuiContextScope&) = delete;
  ImGuiContextScope& operator=(const ImGuiContextScope&) = delete;

 private:
  ImGuiContext* previous_;
};

}  // namespace

std::unique_ptr<ImGuiOffscreen> ImGuiOffscreen::create(int width, int height, std::string* error,
                                                       const ImGuiOffscreenOptions& options) {
  std::unique_ptr<ImGuiOffscreen> self(new ImGuiOffscreen());
  self->options_ = options;
  self->renderer_ = OffscreenRenderer::create(width, height, error, options.samples);
  if (!self->renderer_) return nullptr;

  // A context of our own, with nothing written to disk (no imgui.ini, no log).
  ImGuiContext* previous = ImGui::GetCurrentContext();
  self->imgui_context_ = ImGui::CreateContext();
  ImGui::SetCurrentContext(previous);  // undo CreateContext making it current when none was
  ImGuiContextScope scope(self->imgui_context_);
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;
  io.LogFilename = nullptr;
  io.DisplaySize = ImVec2(static_cast<float>(width), static_cast<float>(height));
  ImGui::StyleColorsDark();

  // The font: the caller's file, else DejaVu Sans, else the built-in one. Checked for
  // readability first, as ImGui treats a missing font file as a programmer error.
  std::string font = options.font_path.empty() ? kDejaVuSans : options.font_path;
  if (readable(font) &&
      io.Fonts->AddFontFromFileTTF(font.c_str(), options.font_size_px) != nullptr) {
    self->font_path_ = font;
  } else if (!options.font_path.empty()) {
    if (error) *error = "ImGuiOffscreen: cannot load font file " + options.font_path;
    return nullptr;
  } else {
    ImFontConfig config;
    config.SizePixels = options.font_size_px;
    io.Fonts->AddFontDefault(&config);
  }

  if (!self->renderer_->context().make_current(error)) return nullptr;
  self->imgui_renderer_ = ImGuiGlRenderer::create(self->renderer_->context().gl(), error);
  if (!self->imgui_renderer_) return nullptr;
  return self;
}

ImGuiOffscreen::~ImGuiOffscreen() {
  if (!imgui_context_) return;
  {
    ImGuiContextScope scope(imgui_context_);
    if (renderer_) renderer_->context().make_current(nullptr);
    imgui_renderer_.reset();
  }
  ImGui::DestroyContext(imgui_context_);  // clears the current context only if it was ours
}

bool ImGuiOffscreen::render(const RenderScene* scene, const ImGuiDrawFunction& draw_ui,
                            std::vector<std::uint8_t>* rgb, std::string* error) {
  ImGuiContextScope scope(imgui_context_);
  ImGuiIO& io = ImGui::GetIO();
  io.DisplaySize = ImVec2(static_cast<float>(width()), static_cast<float>(height()));
  io.DeltaTime = 1.0f / 60.0f;
  io.MousePos = ImVec2(-FLT_MAX, -FLT_MAX);  // no pointer: nothing hovered

  // Run the UI a few frames so windows that size themselves to their content settle; only
  // the last frame's draw data is drawn.
  const int frames = std::max(options_.settle_frames, 1);
  for (int f = 0; f < frames; ++f) {
    ImGui::NewFrame();
    if (draw_ui) draw_ui();
    ImGui::Render();
  }
  const ImDrawData* draw_data = ImGui::GetDrawData();

  auto draw_overlay = [&](const GlFunctions& gl, int w, int h, std::string*) {
    imgui_renderer_->render(draw_data, w, h);
    return true;
  };
  if (scene) return renderer_->render(*scene, rgb, error, nullptr, draw_overlay);

  // No scene: clear to the background and draw the UI alone.
  OffscreenContext& ctx = renderer_->context();
  if (!ctx.make_current(error)) return false;
  ctx.begin_frame();
  const GlFunctions& gl = ctx.gl();
  gl.Viewport(0, 0, width(), height());
  gl.ClearColor(options_.clear_rgb.x(), options_.clear_rgb.y(), options_.clear_rgb.z(), 1.0f);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  draw_overlay(gl, width(), height(), error);
  if (!ctx.end_frame(error)) return false;
  if (rgb) *rgb = ctx.rgb_top_down();
  return true;
}

bool render_imgui_to_png(const RenderScene* scene, int width, int height,
                         const ImGuiDrawFunction& draw_ui, const std::string& path,
                         std::string* error, const ImGuiOffscreenOptions& options) {
  std::unique_ptr<ImGuiOffscreen> ui = ImGuiOffscreen::create(width, height, error, options);
  if (!ui) return false;
  std::vector<std::uint8_t> rgb;
  if (!ui->render(scene, draw_ui, &rgb, error)) return false;
  return write_png_rgb(path, width, height, rgb, error);
}

}  // namespace acdr
