// `acdr dashboard`.
#include "cli/dashboard_command.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <thread>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>

#include "ui/dashboard_model.hpp"
#include "ui/dashboard_view.hpp"
#include "ui/imgui_gl_renderer.hpp"
#include "ui/imgui_offscreen.hpp"
#include "ui/imgui_style.hpp"
#include "ui/png_writer.hpp"
#include "ui/trainee_view.hpp"
// Our GL header (via glfw_window.hpp) before GLFW's.
#include "ui/glfw_window.hpp"
#include <GLFW/glfw3.h>

namespace acdr {
namespace {

// The selection the options ask for; false with `error` when they name what is not there.
bool select(const DashboardModel& model, const DashboardOptions& o, DashboardSelection* sel,
            std::string* error) {
  *sel = default_selection(model);
  if (!o.trainee.empty()) {
    const DashboardTrainee* t = model.find_trainee(o.trainee);
    if (!t) {
      *error = "no trainee '" + o.trainee + "' in " + model.db_path;
      return false;
    }
    sel->trainee_id = o.trainee;
    sel->attempt_id = 0;
    for (auto it = t->attempts.rbegin(); it != t->attempts.rend(); ++it) {
      if (it->status == AttemptStatus::kCompleted) {
        sel->attempt_id = it->id;
        sel->module_id = it->module_id;
        break;
      }
    }
  }
  if (!o.module.empty()) {
    if (!model.find_module(o.module)) {
      *error = "no module '" + o.module + "' in " + model.db_path;
      return false;
    }
    sel->module_id = o.module;
  }
  if (o.attempt >= 0) sel->attempt_id = o.attempt;
  return true;
}

bool write_text(const std::string& path, const std::string& text, std::string* error) {
  std::ofstream file(path, std::ios::binary);
  file << text;
  if (!file) {
    *error = path + ": cannot write";
    return false;
  }
  return true;
}

int run_window(const DashboardOptions& options, Database& db, DashboardModel model,
               DashboardSelection sel, std::unique_ptr<AttemptDrillDown> attempt,
               std::ostream& err) {
  GlfwWindowOptions wo;
  wo.width = options.width;
  wo.height = options.height;
  wo.title = "ACDR Trainer - instructor dashboard";
  std::string error;
  auto window = GlfwWindow::create(wo, &error);
  if (!window) {
    err << "cannot open the dashboard window: " << error << "\n";
    return 2;
  }
  ImGuiContext* context = ImGui::CreateContext();
  ImGui::SetCurrentContext(context);
  ImGui::GetIO().IniFilename = nullptr;
  setup_imgui_style(16.0f);
  ImGui_ImplGlfw_InitForOpenGL(window->handle(), true);
  auto renderer = ImGuiGlRenderer::create(window->gl(), &error);
  if (!renderer) {
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext(context);
    err << "cannot draw the dashboard: " << error << "\n";
    return 2;
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
    if (actions.attempt_changed || (sel.attempt_id > 0 && (!attempt || attempt->record.id != sel.attempt_id))) {
      attempt.reset();
      if (sel.attempt_id > 0) {
        attempt = load_drill_down(db, sel.attempt_id, &error);
        if (!attempt) status = error;
      }
    }
    if (actions.export_csv) {
      const std::string path =
          (std::filesystem::path(options.export_dir) / dashboard_csv_name(sel, attempt.get()))
              .string();
      status = write_text(path, dashboard_csv(model, sel, attempt.get()), &error)
                   ? "Exported " + path
                   : error;
    }
    std::this_thread::sleep_until(frame_start + std::chrono::microseconds(16667));
  }
  renderer.reset();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext(context);
  return 0;
}

}  // namespace

int run_dashboard(const DashboardOptions& options, std::ostream& out, std::ostream& err) {
  const std::string path = options.db.empty() ? default_database_path() : options.db;
  // A reader: never create a record, never mark others' attempts.
  auto db = Database::open(path, OpenOptions{.create = false});
  if (!db) {
    err << db.error().message << "\n";
    return 1;
  }
  auto model = load_dashboard(db.value());
  if (!model) {
    err << model.error().message << "\n";
    return 1;
  }
  DashboardSelection sel;
  std::string error;
  if (!select(model.value(), options, &sel, &error)) {
    err << error << "\n";
    return 2;
  }
  std::unique_ptr<AttemptDrillDown> attempt;
  if (sel.attempt_id > 0) {
    attempt = load_drill_down(db.value(), sel.attempt_id, &error);
    if (!attempt) {
      err << error << "\n";
      return 2;
    }
    sel.replay_t_s = options.replay_t_s >= 0 ? options.replay_t_s : 0.6 * attempt->duration_s;
  }

  if (!options.export_csv.empty()) {
    if (!write_text(options.export_csv, dashboard_csv(model.value(), sel, attempt.get()), &error)) {
      err << error << "\n";
      return 2;
    }
    out << "wrote " << options.export_csv << "\n";
    if (options.screenshot.empty()) return 0;
  }
  if (!options.screenshot.empty()) {
    ImGuiOffscreenOptions look;
    look.settle_frames = 4;
    std::unique_ptr<ImGuiOffscreen> ui =
        ImGuiOffscreen::create(options.width, options.height, &error, look);
    if (!ui) {
      err << error << "\n";
      return 2;
    }
    // The dashboard's own style (the offscreen context starts with ImGui's defaults).
    ImGuiContext* previous = ImGui::GetCurrentContext();
    ImGui::SetCurrentContext(ui->imgui_context());
    ImGuiStyle& style = ImGui::GetStyle();
    style.WindowRounding = 4.0f;
    style.FrameRounding = 3.0f;
    style.ItemSpacing = ImVec2(8, 5);
    ImGui::SetCurrentContext(previous);
    std::vector<std::uint8_t> rgb;
    const bool ok = ui->render(
        nullptr,
        [&] {
          draw_dashboard(model.value(), sel, attempt.get(), "", ImGui::GetIO().DisplaySize,
                         nullptr);
        },
        &rgb, &error);
    if (!ok || !write_png_rgb(options.screenshot, options.width, options.height, rgb, &error)) {
      err << options.screenshot << ": " << error << "\n";
      return 2;
    }
    out << "wrote " << options.screenshot << "\n";
    return 0;
  }
  if (!display_available()) {
    err << "acdr dashboard needs a display for its window (or use --screenshot FILE)\n";
    return 2;
  }
  return run_window(options, db.value(), std::move(model.value()), sel, std::move(attempt), err);
}

}  // namespace acdr
