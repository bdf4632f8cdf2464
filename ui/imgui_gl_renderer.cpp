// ImGui draw lists -> GL 3.3 core, through the function table. Follows the structure of Dear
// ImGui's own opengl3 backend (orthographic projection over the display rectangle, one draw
// call per command, clip rectangles as scissor boxes), written anew on GlFunctions.
#include "ui/imgui_gl_renderer.hpp"

#include <cstddef>
#include <cstdint>

#include <imgui.h>

namespace acdr {

namespace {

const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec2 a_position;  // ImGui display coordinates, pixels
layout(location = 1) in vec2 a_uv;
layout(location = 2) in vec4 a_color;
uniform mat4 u_projection;
out vec2 v_uv;
out vec4 v_color;
void main() {
  v_uv = a_uv;
  v_color = a_color;
  gl_Position = u_projection * vec4(a_position, 0.0, 1.0);
}
)";

const char* kFragmentShader = R"(#version 330 core
in vec2 v_uv;
in vec4 v_color;
uniform sampler2D u_texture;
out vec4 out_color;
void main() { out_color = v_color * texture(u_texture, v_uv); }
)";

const char* kBackendName = "acdr_imgui_gl_renderer";

}  // namespace

std::unique_ptr<ImGuiGlRenderer> ImGuiGlRenderer::create(const GlFunctions& gl,
                                                         std::string* error) {
  if (!ImGui::GetCurrentContext()) {
    if (error) *error = "ImGuiGlRenderer: no current ImGui context (call ImGui::CreateContext)";
    return nullptr;
  }
  if (!gl.missing().empty()) {
    if (error) *error = "ImGuiGlRenderer: GL table not loaded";
    return nullptr;
  }
  std::unique_ptr<ImGuiGlRenderer> r(new ImGuiGlRenderer(gl));
  if (!r->init(error)) return nullptr;
  return r;
}

bool ImGuiGlRenderer::init(std::string* error) {
  const char* sources[2] = {kVertexShader, kFragmentShader};
  const GLenum kinds[2] = {GL_VERTEX_SHADER, GL_FRAGMENT_SHADER};
  GLuint shaders[2] = {0, 0};
  for (int i = 0; i < 2; ++i) {
    shaders[i] = gl_.CreateShader(kinds[i]);
    gl_.ShaderSource(shaders[i], 1, &sources[i], nullptr);
    gl_.CompileShader(shaders[i]);
    GLint ok = GL_FALSE;
    gl_.GetShaderiv(shaders[i], GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
      char log[2048] = {0};
      gl_.GetShaderInfoLog(shaders[i], sizeof(log), nullptr, log);
      if (error) *error = std::string("ImGuiGlRenderer: shader does not compile: ") + log;
      for (GLuint s : shaders) {
        if (s) gl_.DeleteShader(s);
      }
      return false;
    }
  }
  program_ = gl_.CreateProgram();
  gl_.AttachShader(program_, shaders[0]);
  gl_.AttachShader(program_, shaders[1]);
  gl_.LinkProgram(program_);
  gl_.DetachShader(program_, shaders[0]);
  gl_.DetachShader(program_, shaders[1]);
  gl_.DeleteShader(shaders[0]);
  gl_.DeleteShader(shaders[1]);
  GLint linked = GL_FALSE;
  gl_.GetProgramiv(program_, GL_LINK_STATUS, &linked);
  if (linked != GL_TRUE) {
    char log[2048] = {0};
    gl_.GetProgramInfoLog(program_, sizeof(log), nullptr, log);
    if (error) *error = std::string("ImGuiGlRenderer: program does not link: ") + log;
    return false;
  }
  loc_projection_ = gl_.GetUniformLocation(program_, "u_projection");
  loc_texture_ = gl_.GetUniformLocation(program_, "u_texture");

  // ImDrawVert: pos (2 floats), uv (2 floats), col (4 unsigned bytes, normalised).
  gl_.GenVertexArrays(1, &vao_);
  gl_.GenBuffers(1, &vbo_);
  gl_.GenBuffers(1, &ebo_);
  gl_.BindVertexArray(vao_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, vbo_);
  gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_);
  gl_.EnableVertexAttribArray(0);
  gl_.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(ImDrawVert),
                          reinterpret_cast<const void*>(offsetof(ImDrawVert, pos)));
  gl_.EnableVertexAttribArray(1);
  gl_.VertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, sizeof(ImDrawVert),
                          reinterpret_cast<const void*>(offsetof(ImDrawVert, uv)));
  gl_.EnableVertexAttribArray(2);
  gl_.VertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(ImDrawVert),
                          reinterpret_cast<const void*>(offsetof(ImDrawVert, col)));
  gl_.BindVertexArray(0);
  gl_.BindBuffer(GL_ARRAY_BUFFER, 0);

  rebuild_font_texture();

  // Register as the context's renderer: with vertex offsets, draw lists may exceed 64k
  // vertices although indices stay 16-bit.
  ImGuiIO& io = ImGui::GetIO();
  io.BackendRendererName = kBackendName;
  io.BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;
  imgui_context_ = ImGui::GetCurrentContext();

  const std::string gl_error = gl_error_string(gl_, "ImGuiGlRenderer::create");
  if (!gl_error.empty()) {
    if (error) *error = gl_error;
    return false;
  }
  return true;
}

void ImGuiGlRenderer::rebuild_font_texture() {
  ImGuiIO& io = ImGui::GetIO();
  unsigned char* pixels = nullptr;
  int width = 0, height = 0;
  io.Fonts->GetTexDataAsRGBA32(&pixels, &width, &height);
  if (!font_texture_) gl_.GenTextures(1, &font_texture_);
  gl_.BindTexture(GL_TEXTURE_2D, font_texture_);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  gl_.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
  gl_.BindTexture(GL_TEXTURE_2D, 0);
  io.Fonts->SetTexID(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(font_texture_)));
}

ImGuiGlRenderer::~ImGuiGlRenderer() {
  if (font_texture_) gl_.DeleteTextures(1, &font_texture_);
  if (vbo_) gl_.DeleteBuffers(1, &vbo_);
  if (ebo_) gl_.DeleteBuffers(1, &ebo_);
  if (vao_) gl_.DeleteVertexArrays(1, &vao_);
  if (program_) gl_.DeleteProgram(program_);
  if (imgui_context_ && ImGui::GetCurrentContext() == imgui_context_) {
    ImGuiIO& io = ImGui::GetIO();
    io.BackendRendererName = nullptr;
    io.BackendFlags &= ~ImGuiBackendFlags_RendererHasVtxOffset;
    io.Fonts->SetTexID(nullptr);
  }
}

void ImGuiGlRenderer::setup_state(const ImDrawData* draw_data, int fb_width, int fb_height) {
  gl_.Enable(GL_BLEND);
  gl_.BlendEquation(GL_FUNC_ADD);
  gl_.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  gl_.Disable(GL_CULL_FACE);
  gl_.Disable(GL_DEPTH_TEST);
  gl_.Enable(GL_SCISSOR_TEST);
  gl_.Viewport(0, 0, fb_width, fb_height);
  // Orthographic projection of the display rectangle, y down (ImGui's convention).
  const float l = draw_data->DisplayPos.x;
  const float r = draw_data->DisplayPos.x + draw_data->DisplaySize.x;
  const float t = draw_data->DisplayPos.y;
  const float b = draw_data->DisplayPos.y + draw_data->DisplaySize.y;
  const float projection[16] = {
      2.0f / (r - l),    0.0f,              0.0f,  0.0f,
      0.0f,              2.0f / (t - b),    0.0f,  0.0f,
      0.0f,              0.0f,              -1.0f, 0.0f,
      (r + l) / (l - r), (t + b) / (b - t), 0.0f,  1.0f,
  };
  gl_.UseProgram(program_);
  gl_.Uniform1i(loc_texture_, 0);
  gl_.UniformMatrix4fv(loc_projection_, 1, GL_FALSE, projection);
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.BindVertexArray(vao_);  // holds the element buffer binding
  gl_.BindBuffer(GL_ARRAY_BUFFER, vbo_);  // not vertex-array state: bind it here
}

void ImGuiGlRenderer::render(const ImDrawData* draw_data, int fb_width, int fb_height) {
  if (!draw_data || fb_width <= 0 || fb_height <= 0 || draw_data->DisplaySize.x <= 0.0f ||
      draw_data->DisplaySize.y <= 0.0f) {
    return;
  }
  const GLboolean depth_was_on = gl_.IsEnabled(GL_DEPTH_TEST);
  setup_state(draw_data, fb_width, fb_height);
  const ImVec2 clip_offset = draw_data->DisplayPos;
  const ImVec2 clip_scale = draw_data->FramebufferScale;
  for (int n = 0; n < draw_data->CmdListsCount; ++n) {
    const ImDrawList* list = draw_data->CmdLists[n];
    gl_.BufferData(GL_ARRAY_BUFFER,
                   static_cast<GLsizeiptr>(list->VtxBuffer.Size) * sizeof(ImDrawVert),
                   list->VtxBuffer.Data, GL_STREAM_DRAW);
    gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER,
                   static_cast<GLsizeiptr>(list->IdxBuffer.Size) * sizeof(ImDrawIdx),
                   list->IdxBuffer.Data, GL_STREAM_DRAW);
    for (int c = 0; c < list->CmdBuffer.Size; ++c) {
      const ImDrawCmd& cmd = list->CmdBuffer[c];
      if (cmd.UserCallback) {
        if (cmd.UserCallback == ImDrawCallback_ResetRenderState) {
          setup_state(draw_data, fb_width, fb_height);
        } else {
          cmd.UserCallback(list, &cmd);
        }
        continue;
      }
      // Clip rectangle in framebuffer pixels; GL's scissor origin is the bottom-left corner.
      const float x0 = (cmd.ClipRect.x - clip_offset.x) * clip_scale.x;
      const float y0 = (cmd.ClipRect.y - clip_offset.y) * clip_scale.y;
      const float x1 = (cmd.ClipRect.z - clip_offset.x) * clip_scale.x;
      const float y1 = (cmd.ClipRect.w - clip_offset.y) * clip_scale.y;
      if (x1 <= x0 || y1 <= y0) continue;
      gl_.Scissor(static_cast<GLint>(x0), static_cast<GLint>(fb_height - y1),
                  static_cast<GLsizei>(x1 - x0), static_cast<GLsizei>(y1 - y0));
      gl_.BindTexture(GL_TEXTURE_2D,
                      static_cast<GLuint>(reinterpret_cast<std::intptr_t>(cmd.GetTexID())));
      gl_.DrawElementsBaseVertex(
          GL_TRIANGLES, static_cast<GLsizei>(cmd.ElemCount),
          sizeof(ImDrawIdx) == 2 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT,
          reinterpret_cast<const void*>(static_cast<std::intptr_t>(cmd.IdxOffset *
                                                                   sizeof(ImDrawIdx))),
          static_cast<GLint>(cmd.VtxOffset));
    }
  }
  gl_.BindTexture(GL_TEXTURE_2D, 0);
  gl_.BindVertexArray(0);
  gl_.UseProgram(0);
  gl_.Disable(GL_SCISSOR_TEST);
  gl_.Disable(GL_BLEND);
  if (depth_was_on) gl_.Enable(GL_DEPTH_TEST);
}

}  // namespace acdr
