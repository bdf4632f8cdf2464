// The dashboard's window loop and its offscreen picture.
#include "ui/dashboard_window.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>

#include "ui/dashboard_view.hpp"
#include "ui/imgui_gl_renderer.hpp"
#include "ui/imgui_offscreen.hpp"
#include "ui/imgui_style.hpp"
#include "ui/png_writer.hpp"
// Our GL header (via glfw_window.hpp) before GLFW's.
#include "ui/glfw_window.hpp"
#include <GLFW/glfw3.h>

namespace acdr {

bool write_dashboard_csv(const DashboardModel& model, const DashboardSelection& selection,
                         const AttemptDrillDown* attempt, const std::string& path,
                         std::string* error) {
  std::ofstream file(path, std::ios::binary);
  file << dashboard_csv(model, selection, attempt);
  if (!file) {
    *error = path + ": cannot write";
    return false;
  }
  return true;
}

bool run_dashboard_window(const DashboardWindowOptions& options, Database& db,
                          DashboardModel model, DashboardSelection sel,
                          std::unique_ptr<AttemptDrillDown> attempt, std::string* error) {
  GlfwWindowOptions wo;
  wo.width = options.width;
  wo.height = options.height;
  wo.title = "ACDR Trainer - instructor dashboard";
  std::string why;
  auto window = GlfwWindow::create(wo, &why);
  if (!window) {
    *error = "cannot open the dashboard window: " + why;
    return false;
  }
  ImGuiContext* context = ImGui::CreateContext();
  ImGui::SetCurrentContext(context);
  ImGui::GetIO().IniFilename = nullptr;
  setup_imgui_style(16.0f);
  ImGui_ImplGlfw_InitForOpenGL(window->handle(), true);
  auto renderer = ImGuiGlRenderer::create(window->gl(), &why);
  if (!renderer) {
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext(context);
    *error = "cannot draw the dashboard: " + why;
    return false;
  }
  std::string status = "Select a trainee, a module cell or an attempt.";
  auto last_refresh = std::chrono::steady_clock::now();
  const GlFunctions& gl = window->gl();
  while (!window->should_close()) {
    const auto frame_start = std::chrono::steady_clock::now();
    GlfwWindow::poll_events();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    DashboardActions actions;
    draw_dashboard(model, sel, attempt.get(), status, ImGui::GetIO().DisplaySize, &actions);
    ImGui::Render();
    int w = 0, h = 0;
    window->framebuffer_size(&w, &h);
    gl.Viewport(0, 0, w, h);
    gl.ClearColor(0.10f, 0.105f, 0.12f, 1.0f);
    gl.Clear(GL_COLOR_BUFFER_BIT);
    renderer->render(ImGui::GetDrawData(), w, h);
    window->swap_buffers();

    // Readers and a running attempt share the file (WAL): refresh every few seconds.
    if (actions.refresh ||
        std::chrono::steady_clock::now() - last_refresh > std::chrono::seconds(5)) {
      if (auto fresh = load_dashboard(db)) {
        model = std::move(fresh.value());
        if (actions.refresh) status = "Refreshed.";
      } else {
        status = fresh.error().message;
      }
      last_refresh = std::chrono::steady_clock::now();
    }
    if (actions.attempt_changed ||
        (sel.attempt_id > 0 && (!attempt || attempt->record.id != sel.attempt_id))) {
      attempt.reset();
      if (sel.attempt_id > 0) {
        attempt = load_drill_down(db, sel.attempt_id, &why);
        if (!attempt) status = why;
        if (attempt && actions.attempt_changed) sel.replay_t_s = attempt->opening_t_s();
      }
    }
    if (actions.export_csv) {
      const std::string path =
          (std::filesystem::path(options.export_dir) / dashboard_csv_name(sel, attempt.get()))
              .string();
      status = write_dashboard_csv(model, sel, attempt.get(), path, &why) ? "Exported " + path
                                                                           : why;
    }
    std::this_thread::sleep_until(frame_start + std::chrono::microseconds(16667));
  }
  renderer.reset();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext(context);
  return true;
}

bool write_dashboard_png(const DashboardModel& model, const DashboardSelection& selection,
                         const AttemptDrillDown* attempt, int width, int height,
                         const std::string& path, std::string* error) {
  ImGuiOffscreenOptions look;
  look.settle_frames = 4;
  std::unique_ptr<ImGuiOffscreen> ui = ImGuiOffscreen::create(width, height, error, look);
  if (!ui) return false;
  // The dashboard's own style (the offscreen context starts with ImGui's defaults).
  ImGuiContext* previous = ImGui::GetCurrentContext();
  ImGui::SetCurrentContext(ui->imgui_context());
  ImGuiStyle& style = ImGui::GetStyle();
  style.WindowRounding = 4.0f;
  style.FrameRounding = 3.0f;
  style.ItemSpacing = ImVec2(8, 5);
  ImGui::SetCurrentContext(previous);
  DashboardSelection sel = selection;  // drawing may move the replay cursor; this picture keeps it
  std::vector<std::uint8_t> rgb;
  std::string why;
  const bool ok = ui->render(
      nullptr,
      [&] { draw_dashboard(model, sel, attempt, "", ImGui::GetIO().DisplaySize, nullptr); },
      &rgb, &why);
  if (!ok || !write_png_rgb(path, width, height, rgb, &why)) {
    *error = path + ": " + why;
    return false;
  }
  return true;
}

}  // namespace acdr
