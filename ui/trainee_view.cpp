// The trainee view's window: input, the newest live view, the scene, the HUD, the score.
#include "ui/trainee_view.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <thread>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>

// Our GL header (glcorearb.h, via glfw_window.hpp) before GLFW's, so GLFW does not pull in the
// legacy GL/gl.h.
#include "ui/glfw_window.hpp"
#include <GLFW/glfw3.h>

#include "engine/anatomy/anatomy.hpp"
#include "ui/depth_cue.hpp"
#include "ui/display.hpp"
#include "ui/imgui_gl_renderer.hpp"
#include "ui/imgui_style.hpp"
#include "ui/live_bone_stress.hpp"
#include "ui/mouse_instrument.hpp"
#include "ui/orbit_camera.hpp"
#include "ui/png_writer.hpp"
#include "ui/scene_renderer.hpp"
#include "ui/scene_snapshot.hpp"
#include "ui/trainee_hud.hpp"

namespace acdr {
namespace {

using Clock = std::chrono::steady_clock;

// ~60 Hz even without vsync (Xvfb): the haptic thread needs the CPU more than extra frames do.
constexpr auto kFramePeriod = std::chrono::microseconds(16667);
// Mouse mode's camera: from the side (+x), 35 degrees above the horizontal, so that depth
// shows as up and down on the screen and the disc space is seen edge-on between the bodies
// (from the feet, the lower vertebra hides it). A drag to the right moves toward the head,
// a drag up moves away across the work.
constexpr float kMouseViewYawRad = 1.5708f;
constexpr float kMouseViewPitchRad = 0.61f;

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

// The window and what persists from the live phase to the score screen.
struct TraineeView::Window {
  const ScenarioModel* scenario = nullptr;
  const World* world = nullptr;
  std::unique_ptr<GlfwWindow> window;
  std::unique_ptr<SceneRenderer> renderer;
  WindowImGui imgui;
  std::atomic<std::uint64_t>* frames_shown = nullptr;  ///< TraineeView's counter
  std::unique_ptr<MouseInstrumentDevice> mouse;  ///< when the view drives the instrument
  InputDevice* device = nullptr;
  std::string input_label;
  LiveView view;  ///< the newest live view (the last one once the attempt has ended)
  OrbitCamera orbit;
  bool camera_ready = false;
  KeyEdge enter_key, keypad_enter_key, reset_key, stress_key, beads_key, exchange_key;
  bool stress_view = false;  ///< the bone stress view is on (key B or the Controls checkbox)
  bool stress_key_pressed = false;
  LiveBoneStress stress;
  std::vector<std::uint64_t> bone_ids;  ///< the anatomy's vertebra meshes in the scene
  SnapshotOptions drawing;        ///< surfaces or beads (key P)
  MaterialSurfaceCache surfaces;  ///< material surfaces kept while their particles rest
  DepthReference depth;  ///< mouse mode: what the depth cue measures against

  // One frame's state between begin_frame and end_frame.
  Clock::time_point frame_start;
  Clock::time_point last_input = Clock::now();  ///< the last frame that read the keys
  int fb_w = 0, fb_h = 0;
  float aspect = 1.0f;
  RenderScene scene;
  bool enter = false;

  // Polls input and starts a frame: the scene of the newest view, camera controls. Returns
  // false when the window is minimised (nothing to draw) unless `force`.
  bool begin_frame(bool force) {
    frame_start = Clock::now();
    window->framebuffer_size(&fb_w, &fb_h);
    if ((fb_w <= 0 || fb_h <= 0) && !force) {
      std::this_thread::sleep_for(kFramePeriod);
      return false;
    }
    fb_w = std::max(fb_w, 1);
    fb_h = std::max(fb_h, 1);
    aspect = static_cast<float>(fb_w) / static_cast<float>(fb_h);
    drawing.cache = &surfaces;
    scene = snapshot_state(*world, view.state, aspect, {}, drawing);
    if (!camera_ready) {
      reset_camera();
      camera_ready = true;
    }
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    const ImGuiIO& io = ImGui::GetIO();
    // Camera (unless over a HUD window). With a device: right-drag orbit, wheel zoom,
    // middle-drag pan. In mouse mode the left and right buttons and the wheel move the
    // instrument, so: middle-drag orbit, Shift + middle-drag pan, Ctrl + wheel zoom.
    if (!io.WantCaptureMouse) {
      if (!mouse) {
        if (io.MouseDown[1]) orbit.orbit(io.MouseDelta.x, io.MouseDelta.y);
        if (io.MouseDown[2]) orbit.pan(io.MouseDelta.x, io.MouseDelta.y, io.DisplaySize.y);
        if (io.MouseWheel != 0.0f) orbit.zoom(io.MouseWheel);
      } else {
        if (io.MouseDown[2] && io.KeyShift)
          orbit.pan(io.MouseDelta.x, io.MouseDelta.y, io.DisplaySize.y);
        else if (io.MouseDown[2])
          orbit.orbit(io.MouseDelta.x, io.MouseDelta.y);
        if (io.MouseWheel != 0.0f && io.KeyCtrl) orbit.zoom(io.MouseWheel);
      }
    }
    GLFWwindow* handle = window->handle();
    const bool keyboard_free = !io.WantCaptureKeyboard;
    if (keyboard_free && reset_key.pressed(handle, GLFW_KEY_R)) reset_camera();
    stress_key_pressed = keyboard_free && stress_key.pressed(handle, GLFW_KEY_B);
    if (keyboard_free && beads_key.pressed(handle, GLFW_KEY_P)) {
      drawing.drawing = drawing.drawing == MaterialDrawing::kBeads ? MaterialDrawing::kSurfaces
                                                                   : MaterialDrawing::kBeads;
    }
    enter = keyboard_free && (enter_key.pressed(handle, GLFW_KEY_ENTER) ||
                              keypad_enter_key.pressed(handle, GLFW_KEY_KP_ENTER));
    return true;
  }

  // The default view of the work area; in mouse mode from the side and lower down.
  void reset_camera() {
    orbit.reset(scene.camera);
    if (mouse) orbit.set_angles(kMouseViewYawRad, kMouseViewPitchRad);
  }

  // The instrument from the mouse and keyboard, when the view drives it.
  void move_mouse_instrument() {
    if (!mouse) return;
    const ImGuiIO& io = ImGui::GetIO();
    GLFWwindow* handle = window->handle();
    MouseKeyInput in;
    // Held keys move by the time since the last frame (a slow window moves as far).
    in.dt_s = std::clamp(std::chrono::duration<double>(frame_start - last_input).count(), 0.0,
                         0.25);
    last_input = frame_start;
    if (!io.WantCaptureMouse) {
      if (io.MouseDown[0] && io.KeyCtrl) {
        in.turn_dx_px = io.MouseDelta.x;
        in.turn_dy_px = io.MouseDelta.y;
      } else if (io.MouseDown[0]) {
        in.drag_dx_px = io.MouseDelta.x;
        in.drag_dy_px = io.MouseDelta.y;
      }
      if (io.MouseDown[1]) in.depth_drag_px = io.MouseDelta.y;
      if (!io.KeyCtrl) in.wheel_notches = io.MouseWheel;
    }
    if (!io.WantCaptureKeyboard) {
      in.up = key_down(handle, GLFW_KEY_W);
      in.down = key_down(handle, GLFW_KEY_S);
      in.tilt_plus = key_down(handle, GLFW_KEY_E);
      in.tilt_minus = key_down(handle, GLFW_KEY_Q);
      in.roll_plus = key_down(handle, GLFW_KEY_D);
      in.roll_minus = key_down(handle, GLFW_KEY_A);
      in.fast = key_down(handle, GLFW_KEY_LEFT_SHIFT) || key_down(handle, GLFW_KEY_RIGHT_SHIFT);
      in.hold = key_down(handle, GLFW_KEY_SPACE);
      mouse->set_grip(key_down(handle, GLFW_KEY_F) ? 1.0 : 0.0);
      if (exchange_key.pressed(handle, GLFW_KEY_T)) mouse->next_instrument();
    }
    mouse->set_pose(apply_mouse_input(mouse->pose(), in, orbit.camera()));
  }

  // Mouse mode: the drop line to the surface and the depth gauge.
  void draw_depth_cue() {
    if (!mouse) return;
    const DepthCue cue = make_depth_cue(depth, view.state.frame);
    draw_depth_drop_line(cue, orbit.camera(), ImGui::GetIO().DisplaySize);
    draw_depth_gauge(cue, ImGui::GetIO().DisplaySize);
  }

  // Draws the scene and the overlay built since begin_frame.
  void render() {
    scene.camera = orbit.camera();
    ImGui::Render();
    renderer->render(scene, fb_w, fb_h);
    imgui.renderer().render(ImGui::GetDrawData(), fb_w, fb_h);
  }

  // Shows the frame and paces the loop.
  void end_frame() {
    window->swap_buffers();
    frames_shown->fetch_add(1, std::memory_order_relaxed);
    std::this_thread::sleep_until(frame_start + kFramePeriod);
  }
};

TraineeView::TraineeView(TraineeViewOptions options) : options_(std::move(options)) {}
TraineeView::~TraineeView() = default;

bool TraineeView::can_open() const { return display_available(); }

bool TraineeView::open(const ScenarioModel& scenario, const World& world, InputDevice* device,
                       std::string* error) {
  auto w = std::make_unique<Window>();
  w->scenario = &scenario;
  w->world = &world;
  GlfwWindowOptions window_options;
  window_options.width = options_.width;
  window_options.height = options_.height;
  window_options.title = "ACDR Trainer - " + scenario.title;
  window_options.vsync = options_.vsync;
  w->window = GlfwWindow::create(window_options, error);
  if (!w->window) return false;
  w->renderer = SceneRenderer::create(w->window->gl(), error);
  if (!w->renderer) return false;
  if (!w->imgui.init(*w->window, error)) return false;
  // A key pressed and released between two frames still counts (a slow frame loses no Enter).
  glfwSetInputMode(w->window->handle(), GLFW_STICKY_KEYS, GLFW_TRUE);
  w->frames_shown = &frames_shown_;
  // The instrument's input: the given device, or the mouse and keyboard.
  w->device = device;
  if (!device) {
    w->mouse = std::make_unique<MouseInstrumentDevice>(scenario.world.instrument_start);
    w->device = w->mouse.get();
  }
  if (const Anatomy* anatomy = world.anatomy())
    for (VertebraLevel level : {VertebraLevel::kC4, VertebraLevel::kC5})
      w->bone_ids.push_back(anatomy->vertebra(level).content_hash() | 1u);  // as scene_snapshot
  if (options_.beads) w->drawing.drawing = MaterialDrawing::kBeads;
  w->input_label = w->mouse ? "mouse and keyboard"
                            : (options_.input_label.empty() ? "device" : options_.input_label);
  // The first view straight from the world, before anything steps it.
  capture_world_state(world, w->view.state);
  w->depth = depth_reference(world, w->view.state);
  window_ = std::move(w);
  return true;
}

InputDevice& TraineeView::device() { return *window_->device; }

void TraineeView::watch(LiveAttempt& live) {
  Window& w = *window_;
  // The mouse's grip moves by the attempt's simulated seconds (the same scoop in slow motion).
  if (w.mouse) w.mouse->count_time_by([&live] { return live.simulated_time_s(); });
  if (options_.stress_view && live.bone_worker()) {
    w.stress_view = true;
    live.bone_worker()->set_field_wanted(true);
  }
  bool screenshot_done = options_.screenshot.empty();
  for (;;) {
    GlfwWindow::poll_events();
    if (w.window->should_close()) live.request_stop(AttemptEnd::kStopped);
    // Read before the view, so that the frame that sees the end shows the final state.
    const bool finished = live.finished();
    live.latest(w.view);
    if (!w.begin_frame(finished)) continue;
    w.move_mouse_instrument();
    HudModel hud = make_hud_model(*w.scenario, w.world->summary(), w.view, live.haptic_stats(),
                                  w.input_label);
    hud.mouse_mode = w.mouse != nullptr;
    BoneStressWorker* bone = live.bone_worker();
    hud.stress_view_available = bone != nullptr;
    hud.stress_view_on = w.stress_view;
    HudActions actions;
    draw_trainee_hud(hud, ImGui::GetIO().DisplaySize, &actions);
    if (bone && (actions.toggle_stress_view || w.stress_key_pressed)) {
      w.stress_view = !w.stress_view;
      bone->set_field_wanted(w.stress_view);
    }
    if (bone && w.stress_view) {
      w.stress.update(*bone);
      w.stress.apply(w.scene, w.bone_ids);
      w.stress.draw_legend(ImGui::GetIO().DisplaySize, actions.status_bottom);
    }
    w.draw_depth_cue();
    if (actions.reset_camera) w.reset_camera();
    if ((actions.finish || w.enter) && !finished) {
      // "Done": score what was done (for the mouse through the device, like a bridge's
      // end-of-attempt).
      if (w.mouse)
        w.mouse->request_end();
      else
        live.request_stop(AttemptEnd::kInputEnded);
    }
    w.render();
    // The picture, read back before the swap.
    if (!screenshot_done &&
        ((options_.screenshot_at_s >= 0 && w.view.state.frame.t_s >= options_.screenshot_at_s) ||
         (options_.screenshot_at_s < 0 && finished))) {
      std::string error;
      if (!save_window_png(*w.window, options_.screenshot, &error))
        picture_error_ = options_.screenshot + ": " + error;
      screenshot_done = true;
    }
    if (finished) {
      w.window->swap_buffers();
      if (w.mouse) w.mouse->count_time_by({});  // `live` may go before the device
      return;
    }
    w.end_frame();
  }
}

void TraineeView::show_score(const AttemptRun& run, const std::string& status) {
  Window& w = *window_;
  const ScoreScreenModel score = make_score_screen(*w.scenario, run, status);
  const Clock::time_point shown = Clock::now();
  bool screenshot_done = options_.score_screenshot.empty();
  int frames = 0;
  for (;;) {
    GlfwWindow::poll_events();
    if (w.window->should_close()) return;
    if (!w.begin_frame(false)) continue;
    const bool close = draw_score_screen(score, ImGui::GetIO().DisplaySize) || w.enter;
    w.render();
    if (!screenshot_done && ++frames >= 3) {
      // Three frames: the auto-sized score window has settled.
      std::string error;
      if (!save_window_png(*w.window, options_.score_screenshot, &error))
        picture_error_ = options_.score_screenshot + ": " + error;
      screenshot_done = true;
    }
    if (close) {
      w.window->swap_buffers();
      return;
    }
    const double elapsed = std::chrono::duration<double>(Clock::now() - shown).count();
    if (options_.close_after_s >= 0 && elapsed > options_.close_after_s && screenshot_done) {
      w.window->swap_buffers();
      return;
    }
    w.end_frame();
  }
}

}  // namespace acdr
