// OSMesa context creation. osmesa.h is included only here; it pulls in <GL/gl.h>, whose
// prototypes we never call (GL goes through the GlFunctions table).
#include "ui/offscreen_context.hpp"

#include "ui/png_writer.hpp"

#include <GL/osmesa.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>

namespace acdr {

namespace {
OSMesaContext as_osmesa(void* context) { return static_cast<OSMesaContext>(context); }

// Every pointer comes from OSMesaGetProcAddress, which is what libOSMesa's own gl* exports
// resolve to; the cast goes through a plain function pointer, as OSMESAproc is one.
void* osmesa_proc(const char* name) {
  return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
}

std::string gl_string(const GlFunctions& gl, GLenum name) {
  const GLubyte* s = gl.GetString(name);
  return s ? reinterpret_cast<const char*>(s) : "";
}
}  // namespace

std::unique_ptr<OffscreenContext> OffscreenContext::create(int width, int height, int samples,
                                                           std::string* error) {
  if (width <= 0 || height <= 0 || width > 16384 || height > 16384) {
    if (error) {
      *error = "OffscreenContext: image size " + std::to_string(width) + "x" +
               std::to_string(height) + " is out of range (expected 1..16384 on each side)";
    }
    return nullptr;
  }
  std::unique_ptr<OffscreenContext> ctx(new OffscreenContext());
  ctx->width_ = width;
  ctx->height_ = height;

  // Core 3.3 first (what the renderer is written for); compatibility 3.3 next (some Mesa
  // builds offer only that); last the legacy call, which gives whatever Mesa defaults to.
  const int profiles[2] = {OSMESA_CORE_PROFILE, OSMESA_COMPAT_PROFILE};
  for (int profile : profiles) {
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA,
                           OSMESA_DEPTH_BITS, 24,
                           OSMESA_STENCIL_BITS, 8,
                           OSMESA_PROFILE, profile,
                           OSMESA_CONTEXT_MAJOR_VERSION, 3,
                           OSMESA_CONTEXT_MINOR_VERSION, 3,
                           0};
    ctx->context_ = OSMesaCreateContextAttribs(attribs, nullptr);
    if (ctx->context_) {
      ctx->core_ = profile == OSMESA_CORE_PROFILE;
      break;
    }
  }
  if (!ctx->context_) ctx->context_ = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, nullptr);
  if (!ctx->context_) {
    if (error) *error = "OffscreenContext: OSMesa could not create a GL context";
    return nullptr;
  }

  ctx->buffer_.assign(static_cast<std::size_t>(width) * height * 4, 0);
  if (!ctx->make_current(error)) return nullptr;
  if (!ctx->gl_.load(osmesa_proc, error)) {
    if (error) *error = "OffscreenContext: " + *error;
    return nullptr;
  }
  ctx->version_ = gl_string(ctx->gl_, GL_VERSION);
  ctx->renderer_ = gl_string(ctx->gl_, GL_RENDERER);
  // A 3.3 context is the floor: the shaders are GLSL 330.
  int major = 0;
  if (!ctx->version_.empty()) major = std::atoi(ctx->version_.c_str());
  if (major < 3) {
    if (error) {
      *error = "OffscreenContext: OSMesa gave OpenGL '" + ctx->version_ +
               "', expected 3.3 or newer";
    }
    return nullptr;
  }
  ctx->samples_ = std::max(samples, 1);
  if (ctx->samples_ > 1 && !ctx->create_multisample_target(error)) return nullptr;
  return ctx;
}

bool OffscreenContext::create_multisample_target(std::string* error) {
  GLint max_samples = 1;
  gl_.GetIntegerv(GL_MAX_SAMPLES, &max_samples);
  samples_ = std::min(samples_, static_cast<int>(std::max(max_samples, 1)));
  if (samples_ <= 1) {
    samples_ = 1;
    return true;
  }
  gl_.GenFramebuffers(1, &msaa_fbo_);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, msaa_fbo_);
  gl_.GenRenderbuffers(1, &msaa_color_);
  gl_.BindRenderbuffer(GL_RENDERBUFFER, msaa_color_);
  gl_.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_RGBA8, width_, height_);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, msaa_color_);
  gl_.GenRenderbuffers(1, &msaa_depth_);
  gl_.BindRenderbuffer(GL_RENDERBUFFER, msaa_depth_);
  gl_.RenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, GL_DEPTH24_STENCIL8, width_,
                                     height_);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                              msaa_depth_);
  const GLenum status = gl_.CheckFramebufferStatus(GL_FRAMEBUFFER);
  gl_.BindRenderbuffer(GL_RENDERBUFFER, 0);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    // Not fatal: draw without multisampling rather than not at all.
    gl_.DeleteFramebuffers(1, &msaa_fbo_);
    const GLuint rbs[2] = {msaa_color_, msaa_depth_};
    gl_.DeleteRenderbuffers(2, rbs);
    msaa_fbo_ = msaa_color_ = msaa_depth_ = 0;
    samples_ = 1;
  }
  const std::string gl_error = gl_error_string(gl_, "OffscreenContext multisample target");
  if (!gl_error.empty()) {
    if (error) *error = gl_error;
    return false;
  }
  return true;
}

OffscreenContext::~OffscreenContext() {
  if (!context_) return;
  // Delete our GL objects while the context is still current, then the context itself.
  if (msaa_fbo_ && make_current(nullptr)) {
    gl_.DeleteFramebuffers(1, &msaa_fbo_);
    const GLuint rbs[2] = {msaa_color_, msaa_depth_};
    gl_.DeleteRenderbuffers(2, rbs);
  }
  OSMesaDestroyContext(as_osmesa(context_));
}

bool OffscreenContext::make_current(std::string* error) {
  if (!OSMesaMakeCurrent(as_osmesa(context_), buffer_.data(), GL_UNSIGNED_BYTE, width_,
                         height_)) {
    if (error) *error = "OffscreenContext: OSMesaMakeCurrent failed";
    return false;
  }
  return true;
}

void OffscreenContext::begin_frame() {
  gl_.BindFramebuffer(GL_FRAMEBUFFER, msaa_fbo_);  // 0: the OSMesa buffer itself
}

bool OffscreenContext::end_frame(std::string* error) {
  if (msaa_fbo_) {
    gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, msaa_fbo_);
    gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    gl_.BlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT,
                        GL_NEAREST);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
  }
  gl_.Finish();
  const std::string gl_error = gl_error_string(gl_, "OffscreenContext::end_frame");
  if (!gl_error.empty()) {
    if (error) *error = gl_error;
    return false;
  }
  return true;
}

std::vector<std::uint8_t> OffscreenContext::rgb_top_down() const {
  return rgba_bottom_up_to_rgb(buffer_, width_, height_);
}

}  // namespace acdr
