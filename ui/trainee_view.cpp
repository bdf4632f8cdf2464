// The trainee view's window loop: input, the newest live view, the scene, the HUD, the score.
#include "ui/trainee_view.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <memory>
#include <thread>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>

// Our GL header (glcorearb.h, via glfw_window.hpp) before GLFW's, so GLFW does not pull in the
// legacy GL/gl.h.
#include "ui/glfw_window.hpp"
#include <GLFW/glfw3.h>

#include "app/live_attempt.hpp"
#include "ui/imgui_gl_renderer.hpp"
#include "ui/imgui_style.hpp"
#include "ui/mouse_instrument.hpp"
#include "ui/orbit_camera.hpp"
#include "ui/png_writer.hpp"
#include "ui/scene_renderer.hpp"
#include "ui/scene_snapshot.hpp"
#include "ui/trainee_hud.hpp"

namespace acdr {
namespace {

using Clock = std::chrono::steady_clock;

bool key_down(GLFWwindow* w, int key) { return glfwGetKey(w, key) == GLFW_PRESS; }

// Edge detection for keys that act once per press.
struct KeyEdge {
  bool was = false;
  bool pressed(GLFWwindow* w, int key) {
    const bool now = key_down(w, key);
    const bool edge = now && !was;
    was = now;
    return edge;
  }
};

// ImGui with the GLFW platform backend and our GL renderer, torn down in the right order.
class WindowImGui {
 public:
  bool init(GlfwWindow& window, std::string* error) {
    context_ = ImGui::CreateContext();
    ImGui::SetCurrentContext(context_);
    ImGui::GetIO().IniFilename = nullptr;
    ImGui::GetIO().LogFilename = nullptr;
    setup_imgui_style(16.0f);
    glfw_ready_ = ImGui_ImplGlfw_InitForOpenGL(window.handle(), true);
    renderer_ = ImGuiGlRenderer::create(window.gl(), error);
    return glfw_ready_ && renderer_ != nullptr;
  }
  ~WindowImGui() {
    renderer_.reset();
    if (glfw_ready_) ImGui_ImplGlfw_Shutdown();
    if (context_) ImGui::DestroyContext(context_);
  }
  ImGuiGlRenderer& renderer() { return *renderer_; }

 private:
  ImGuiContext* context_ = nullptr;
  bool glfw_ready_ = false;
  std::unique_ptr<ImGuiGlRenderer> renderer_;
};

bool save_window_png(const GlfwWindow& window, const std::string& path, std::string* error) {
  int w = 0, h = 0;
  window.framebuffer_size(&w, &h);
  return write_png_rgb(path, w, h, window.read_back_buffer_rgb(), error);
}

}  // namespace

bool display_available() {
  const char* x = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  return (x && *x) || (wayland && *wayland);
}

TraineeViewOutcome run_trainee_view(const ScenarioModel& scenario, World& world,
                                    InputDevice* device, const TraineeViewOptions& options,
                                    const AttemptFinished& on_finished) {
  TraineeViewOutcome outcome;
  GlfwWindowOptions window_options;
  window_options.width = options.width;
  window_options.height = options.height;
  window_options.title = "ACDR Trainer - " + scenario.title;
  window_options.vsync = options.vsync;
  auto window = GlfwWindow::create(window_options, &outcome.error);
  if (!window) return outcome;
  auto renderer = SceneRenderer::create(window->gl(), &outcome.error);
  if (!renderer) return outcome;
  WindowImGui imgui;
  if (!imgui.init(*window, &outcome.error)) return outcome;
  GLFWwindow* handle = window->handle();

  // The instrument's input: the given device, or the mouse and keyboard.
  std::unique_ptr<MouseInstrumentDevice> mouse;
  InputDevice* input = device;
  if (!input) {
    mouse = std::make_unique<MouseInstrumentDevice>(scenario.world.instrument_start);
    input = mouse.get();
  }
  const std::string input_label =
      mouse ? "mouse and keyboard" : (options.input_label.empty() ? "device" : options.input_label);

  // The first view straight from the world (nothing steps it yet), then the haptic thread.
  LiveView view;
  capture_world_state(world, view.state);
  LiveAttempt live(scenario, world, *input, options.loop);
  live.set_checkpoints(options.checkpoint_every_s, options.checkpoint_sink);
  live.start();

  OrbitCamera orbit;
  bool camera_ready = false;
  bool live_phase = true;
  bool screenshot_done = options.screenshot.empty();
  bool score_screenshot_done = options.score_screenshot.empty();
  int score_frames = 0;
  ScoreScreenModel score;
  Clock::time_point score_shown{};
  KeyEdge enter_key, reset_key;
  const auto frame_period = std::chrono::microseconds(16667);  // ~60 Hz even without vsync

  for (;;) {
    const auto frame_start = Clock::now();
    GlfwWindow::poll_events();
    const bool closing = window->should_close();
    if (closing && live_phase) live.request_stop(AttemptEnd::kStopped);
    if (closing && !live_phase) break;

    // The newest view; `finished_now` read first, so this frame shows the final state.
    const bool finished_now = live_phase && live.finished();
    live.latest(view);

    int fb_w = 0, fb_h = 0;
    window->framebuffer_size(&fb_w, &fb_h);
    if ((fb_w <= 0 || fb_h <= 0) && !finished_now) {  // minimised: nothing to draw
      std::this_thread::sleep_for(frame_period);
      continue;
    }
    fb_w = std::max(fb_w, 1);
    fb_h = std::max(fb_h, 1);
    const float aspect = static_cast<float>(fb_w) / static_cast<float>(fb_h);
    RenderScene scene = snapshot_state(world, view.state, aspect);
    if (!camera_ready) {
      orbit.reset(scene.camera);
      camera_ready = true;
    }

    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const ImGuiIO& io = ImGui::GetIO();

    // Camera: right-drag orbit, wheel zoom, middle-drag pan (unless over a HUD window).
    if (!io.WantCaptureMouse) {
      if (io.MouseDown[1]) orbit.orbit(io.MouseDelta.x, io.MouseDelta.y);
      if (io.MouseDown[2]) orbit.pan(io.MouseDelta.x, io.MouseDelta.y, io.DisplaySize.y);
      if (io.MouseWheel != 0.0f) orbit.zoom(io.MouseWheel);
    }
    const bool keyboard_free = !io.WantCaptureKeyboard;
    if (keyboard_free && reset_key.pressed(handle, GLFW_KEY_R)) orbit.reset(scene.camera);
    const bool enter = keyboard_free && (enter_key.pressed(handle, GLFW_KEY_ENTER) ||
                                         enter_key.pressed(handle, GLFW_KEY_KP_ENTER));

    // Instrument from the mouse and keyboard.
    if (mouse && live_phase) {
      MouseKeyInput in;
      in.dt_s = 1.0 / 60.0;
      if (!io.WantCaptureMouse && io.MouseDown[0]) {
        in.drag_dx_px = io.MouseDelta.x;
        in.drag_dy_px = io.MouseDelta.y;
      }
      if (keyboard_free) {
        in.up = key_down(handle, GLFW_KEY_W);
        in.down = key_down(handle, GLFW_KEY_S);
        in.tilt_plus = key_down(handle, GLFW_KEY_E);
        in.tilt_minus = key_down(handle, GLFW_KEY_Q);
        in.roll_plus = key_down(handle, GLFW_KEY_D);
        in.roll_minus = key_down(handle, GLFW_KEY_A);
        in.fast = key_down(handle, GLFW_KEY_LEFT_SHIFT) || key_down(handle, GLFW_KEY_RIGHT_SHIFT);
        in.hold = key_down(handle, GLFW_KEY_SPACE);
      }
      mouse->set_pose(apply_mouse_input(mouse->pose(), in, orbit.camera()));
    }
    scene.camera = orbit.camera();

    // Overlay.
    bool close_score = false;
    if (live_phase) {
      HudModel hud = make_hud_model(scenario, world.summary(), view, live.haptic_stats(),
                                    input_label);
      hud.mouse_mode = mouse != nullptr;
      HudActions actions;
      draw_trainee_hud(hud, io.DisplaySize, &actions);
      if (actions.reset_camera) orbit.reset(snapshot_state(world, view.state, aspect).camera);
      if ((actions.finish || enter) && !finished_now) {
        // "Done": score what was done (for the mouse through the device, like a bridge's
        // end-of-attempt).
        if (mouse)
          mouse->request_end();
        else
          live.request_stop(AttemptEnd::kInputEnded);
      }
    } else {
      close_score = draw_score_screen(score, io.DisplaySize) || enter;
    }
    ImGui::Render();

    const RenderStats stats = renderer->render(scene, fb_w, fb_h);
    (void)stats;
    imgui.renderer().render(ImGui::GetDrawData(), fb_w, fb_h);

    // Pictures, read back before the swap.
    std::string error;
    if (live_phase && !screenshot_done &&
        ((options.screenshot_at_s >= 0 && view.state.frame.t_s >= options.screenshot_at_s) ||
         (options.screenshot_at_s < 0 && finished_now))) {
      if (!save_window_png(*window, options.screenshot, &error))
        outcome.error = options.screenshot + ": " + error;
      screenshot_done = true;
    }
    if (!live_phase && !score_screenshot_done && ++score_frames >= 3) {
      // Three frames: the auto-sized score window has settled.
      if (!save_window_png(*window, options.score_screenshot, &error))
        outcome.error = options.score_screenshot + ": " + error;
      score_screenshot_done = true;
    }
    window->swap_buffers();

    if (finished_now) {
      // The attempt is over: close it (metrics, score), let the caller store it, show the score.
      outcome.run = live.wait();
      outcome.haptics = live.haptic_stats();
      outcome.checkpoints = live.checkpoint_stats();
      const std::string status = on_finished ? on_finished(outcome.run) : "";
      score = make_score_screen(scenario, outcome.run, status);
      live_phase = false;
      score_shown = Clock::now();
      if (outcome.run.end == AttemptEnd::kStopped) break;  // the window was closed
    }
    if (close_score) break;
    if (!live_phase && options.close_after_s >= 0 &&
        std::chrono::duration<double>(Clock::now() - score_shown).count() > options.close_after_s &&
        score_screenshot_done)
      break;
    // Pace the window at ~60 Hz even when the swap does not wait (no vsync, Xvfb): the
    // haptic thread needs the CPU more than extra frames do.
    std::this_thread::sleep_until(frame_start + frame_period);
  }
  if (live_phase) {
    live.request_stop(AttemptEnd::kStopped);
    outcome.run = live.wait();
    outcome.haptics = live.haptic_stats();
    outcome.checkpoints = live.checkpoint_stats();
    if (on_finished) on_finished(outcome.run);
  }
  outcome.ok = true;
  return outcome;
}

}  // namespace acdr
