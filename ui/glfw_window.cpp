// GLFW window creation and the GL table of its context.
#include "ui/glfw_window.hpp"

#include <mutex>

#include <GLFW/glfw3.h>

#include "ui/png_writer.hpp"

namespace acdr {

namespace {

// GLFW is process-wide: initialise it with the first window, terminate it with the last.
std::mutex& glfw_mutex() {
  static std::mutex m;
  return m;
}
int& glfw_users() {
  static int users = 0;
  return users;
}

std::string& last_glfw_error() {
  static thread_local std::string message;
  return message;
}

void on_glfw_error(int code, const char* description) {
  last_glfw_error() = "GLFW error " + std::to_string(code) + ": " + (description ? description : "");
}

bool acquire_glfw(std::string* error) {
  std::lock_guard<std::mutex> lock(glfw_mutex());
  if (glfw_users() == 0) {
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
      if (error) *error = "GlfwWindow: cannot initialise GLFW (" + last_glfw_error() + ")";
      return false;
    }
  }
  ++glfw_users();
  return true;
}

void release_glfw() {
  std::lock_guard<std::mutex> lock(glfw_mutex());
  if (--glfw_users() == 0) glfwTerminate();
}

}  // namespace

std::unique_ptr<GlfwWindow> GlfwWindow::create(const GlfwWindowOptions& options,
                                               std::string* error) {
  if (!acquire_glfw(error)) return nullptr;
  std::unique_ptr<GlfwWindow> w(new GlfwWindow());
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, std::max(options.samples, 0));
  glfwWindowHint(GLFW_DEPTH_BITS, 24);
  glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
  last_glfw_error().clear();
  w->window_ = glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr,
                                nullptr);
  if (!w->window_) {
    if (error) *error = "GlfwWindow: cannot open a window with OpenGL 3.3 core (" +
                        last_glfw_error() + ")";
    release_glfw();
    return nullptr;
  }
  glfwMakeContextCurrent(w->window_);
  glfwSwapInterval(options.vsync ? 1 : 0);
  if (!w->gl_.load(
          [](const char* name) { return reinterpret_cast<void*>(glfwGetProcAddress(name)); },
          error)) {
    if (error) *error = "GlfwWindow: " + *error;
    return nullptr;  // the destructor closes the window and releases GLFW
  }
  const GLubyte* version = w->gl_.GetString(GL_VERSION);
  w->version_ = version ? reinterpret_cast<const char*>(version) : "";
  return w;
}

GlfwWindow::~GlfwWindow() {
  if (!window_) return;
  if (glfwGetCurrentContext() == window_) glfwMakeContextCurrent(nullptr);
  glfwDestroyWindow(window_);
  release_glfw();
}

void GlfwWindow::make_current() { glfwMakeContextCurrent(window_); }

void GlfwWindow::release_current() { glfwMakeContextCurrent(nullptr); }

bool GlfwWindow::should_close() const { return glfwWindowShouldClose(window_) != 0; }

void GlfwWindow::swap_buffers() { glfwSwapBuffers(window_); }

void GlfwWindow::poll_events() { glfwPollEvents(); }

void GlfwWindow::framebuffer_size(int* width, int* height) const {
  glfwGetFramebufferSize(window_, width, height);
}

std::vector<std::uint8_t> GlfwWindow::read_back_buffer_rgb() const {
  int width = 0, height = 0;
  framebuffer_size(&width, &height);
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(width) * height * 4);
  gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  gl_.ReadBuffer(GL_BACK);
  gl_.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl_.ReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  return rgba_bottom_up_to_rgb(rgba, width, height);
}

}  // namespace acdr
