// An OpenGL context with no display: OSMesa rendering into a buffer in memory (llvmpipe).
// Used by `acdr run --png`, `acdr render`, dashboard screenshots and the UI tests.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ui/gl_functions.hpp"

namespace acdr {

class OffscreenContext {
 public:
  /// Creates a width x height context and makes it current on the calling thread. Asks for a
  /// 3.3+ core profile and falls back to a compatibility profile (and then to the oldest
  /// OSMesa entry point) when that fails. `samples` > 1 adds a multisampled framebuffer
  /// (typically 4) that begin_frame() binds and end_frame() resolves; 1 draws straight into the
  /// buffer. Returns null and an error on failure; never exits.
  static std::unique_ptr<OffscreenContext> create(int width, int height, int samples,
                                                  std::string* error);

  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  /// Makes this context current on the calling thread (an OSMesa context is current on one
  /// thread at a time).
  bool make_current(std::string* error);

  /// The GL entry points of this context.
  const GlFunctions& gl() const { return gl_; }

  int width() const { return width_; }
  int height() const { return height_; }
  int samples() const { return samples_; }       ///< 1 when multisampling is off or unavailable
  bool core_profile() const { return core_; }    ///< false: a compatibility context
  const std::string& version() const { return version_; }    ///< GL_VERSION
  const std::string& renderer() const { return renderer_; }  ///< GL_RENDERER

  /// Binds the framebuffer to draw the next frame into (the multisampled one, if any).
  void begin_frame();
  /// Resolves the multisampled framebuffer into the OSMesa buffer and waits for the GL, so the
  /// pixels can be read. Returns false with the GL error on failure.
  bool end_frame(std::string* error);

  /// The OSMesa colour buffer after end_frame(): RGBA, 8 bits per channel, width*height*4
  /// bytes, bottom row first (GL's convention). Alpha is not opacity: ignore it.
  const std::vector<std::uint8_t>& rgba_bottom_up() const { return buffer_; }

  /// The image after end_frame() as RGB, top row first (width*height*3 bytes), as written to a
  /// PNG.
  std::vector<std::uint8_t> rgb_top_down() const;

 private:
  OffscreenContext() = default;
  bool create_multisample_target(std::string* error);

  void* context_ = nullptr;  ///< OSMesaContext (kept opaque so osmesa.h stays out of headers)
  GlFunctions gl_;
  std::vector<std::uint8_t> buffer_;
  int width_ = 0, height_ = 0, samples_ = 1;
  bool core_ = false;
  std::string version_, renderer_;
  GLuint msaa_fbo_ = 0, msaa_color_ = 0, msaa_depth_ = 0;
};

}  // namespace acdr
