// A desktop window with an OpenGL 3.3 core context (GLFW), whose GL entry points are loaded
// into a GlFunctions table through glfwGetProcAddress, so the scene renderer and the ImGui
// renderer draw into it exactly as they draw offscreen. libGL is never linked: GLFW opens it
// at run time, privately, so it cannot shadow libOSMesa's exports in the same process.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ui/gl_functions.hpp"

struct GLFWwindow;

namespace acdr {

struct GlfwWindowOptions {
  int width = 1280;   ///< window size in screen coordinates
  int height = 720;
  std::string title = "ACDR Trainer";
  int samples = 4;    ///< multisampling of the default framebuffer (0 = off)
  bool visible = true;
  bool vsync = true;  ///< swap at the display's rate (~60 Hz)
};

/// One GLFW window. Create, poll events and destroy it on the main thread (GLFW's rule); its
/// context may be made current on another thread for rendering (one thread at a time).
class GlfwWindow {
 public:
  /// Initialises GLFW on first use (reference counted), opens the window, makes its context
  /// current on the calling thread and loads the GL table. Null and an error (e.g. no
  /// display, no 3.3 core context) on failure.
  static std::unique_ptr<GlfwWindow> create(const GlfwWindowOptions& options, std::string* error);

  ~GlfwWindow();
  GlfwWindow(const GlfwWindow&) = delete;
  GlfwWindow& operator=(const GlfwWindow&) = delete;

  GLFWwindow* handle() const { return window_; }
  const GlFunctions& gl() const { return gl_; }
  const std::string& version() const { return version_; }  ///< GL_VERSION

  /// Makes the window's context current on the calling thread.
  void make_current();
  /// Releases whatever context is current on the calling thread.
  static void release_current();

  bool should_close() const;
  void swap_buffers();
  /// Processes pending window events (main thread only).
  static void poll_events();
  /// The framebuffer's size in pixels (differs from the window size on high-DPI screens).
  void framebuffer_size(int* width, int* height) const;

  /// The back buffer as RGB, top row first (call after drawing, before swap_buffers).
  std::vector<std::uint8_t> read_back_buffer_rgb() const;

 private:
  GlfwWindow() = default;
  GLFWwindow* window_ = nullptr;
  GlFunctions gl_;
  std::string version_;
};

}  // namespace acdr
