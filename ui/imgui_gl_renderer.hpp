// A Dear ImGui renderer backend on the GlFunctions table (OpenGL 3.3 core). It replaces the
// packaged imgui_impl_opengl3, whose loader looks up glXGetProcAddressARB through dlsym and
// fails under OSMesa (docs/dependencies.md), and imgui_impl_opengl2, which calls gl* symbols directly
// (so it needs libGL in a window and a compatibility context offscreen). With this one the same
// code draws ImGui into an OSMesa buffer and into a GLFW window; a window pairs it with the
// packaged imgui_impl_glfw platform backend, which makes no GL calls.
#pragma once

#include <memory>
#include <string>

#include "ui/gl_functions.hpp"

struct ImDrawData;

namespace acdr {

class ImGuiGlRenderer {
 public:
  /// Compiles the shader, uploads the font atlas of the *current* ImGui context and registers
  /// itself as that context's renderer backend (io.BackendRendererName, vertex offsets). The
  /// GL context must be current. Returns null and an error on failure.
  static std::unique_ptr<ImGuiGlRenderer> create(const GlFunctions& gl, std::string* error);

  /// Frees the GL objects (the GL context must be current) and unregisters from the ImGui
  /// context that was current at creation when it is still alive and current.
  ~ImGuiGlRenderer();
  ImGuiGlRenderer(const ImGuiGlRenderer&) = delete;
  ImGuiGlRenderer& operator=(const ImGuiGlRenderer&) = delete;

  /// Draws ImGui's output (ImGui::GetDrawData() after ImGui::Render()) into the currently
  /// bound framebuffer of `framebuffer_width` x `framebuffer_height` pixels, blended over what
  /// is there. Leaves blending, scissor and culling off afterwards and depth test as it found.
  void render(const ImDrawData* draw_data, int framebuffer_width, int framebuffer_height);

  /// Re-uploads the font atlas after fonts were added or rebuilt.
  void rebuild_font_texture();

 private:
  explicit ImGuiGlRenderer(const GlFunctions& gl) : gl_(gl) {}
  bool init(std::string* error);
  void setup_state(const ImDrawData* draw_data, int fb_width, int fb_height);

  GlFunctions gl_;
  GLuint program_ = 0, vao_ = 0, vbo_ = 0, ebo_ = 0, font_texture_ = 0;
  GLint loc_projection_ = -1, loc_texture_ = -1;
  void* imgui_context_ = nullptr;  ///< the ImGuiContext this renderer registered with
};

}  // namespace acdr
