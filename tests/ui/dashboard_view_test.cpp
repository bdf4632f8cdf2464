// Tests of ui/dashboard_view at the size of a common laptop screen, 1280 x 800: every text the
// dashboard lays out fits its pane, column or window (text_fit_probe.hpp measures each against
// the width it was given), metric rows read as words with units, and the picture is kept as
// dashboard_1280x800.png in the working directory for a person to look at.
#include "ui/dashboard_view.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/db/db_test_support.hpp"
#include "tests/ui/test_record.hpp"
#include "tests/ui/text_fit_probe.hpp"
#include "ui/imgui_offscreen.hpp"
#include "ui/png_writer.hpp"

namespace acdr {
namespace {

TEST(DashboardView, EveryLabelFitsAt1280x800) {
  test::TempDir dir;
  const std::string path = dir.file("record.sqlite");
  test::make_test_record(path);
  Database db = test::open_or_fail(path);
  auto model = load_dashboard(db);
  ASSERT_TRUE(model) << model.error().message;
  DashboardSelection sel = default_selection(*model);
  std::string error;
  auto attempt = load_drill_down(db, sel.attempt_id, &error);
  ASSERT_TRUE(attempt) << error;

  const int w = 1280, h = 800;
  auto ui = ImGuiOffscreen::create(w, h, &error);
  ASSERT_TRUE(ui) << error;
  std::vector<std::string> overflows;
  std::vector<std::uint8_t> rgb;
  ASSERT_TRUE(ui->render(
      nullptr,
      [&] {
        draw_dashboard(*model, sel, attempt.get(), "", ImVec2(w, h), nullptr);
        overflows = test::text_overflows(ImVec2(w, h));
      },
      &rgb, &error))
      << error;
  ASSERT_TRUE(write_png_rgb("dashboard_1280x800.png", w, h, rgb, &error)) << error;
  for (const std::string& o : overflows) ADD_FAILURE() << o;
}

// An attempt at the C4-C5 module (its anatomy, four modules in the matrix, the bone stress
// pane) at 1280 x 800: the module chooser, the matrix's headers, the replay and the bone stress
// pane all show whole, with no scrolling (the picture: dashboard_c4c5_1280x800.png).
TEST(DashboardView, AC4C5AttemptShowsItsReplayAndBoneStressAt1280x800) {
  test::TempDir dir;
  const std::string path = dir.file("record.sqlite");
  // The expert's first scoop, cut short: into the nucleus, across, out (3 s).
  const std::string scoop = dir.file("scoop.csv");
  {
    std::ofstream csv(scoop);
    csv << "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n0,0,0,0.1019,1,0,0,0\n0.5,-0.0025,0,0.1019,1,0,0,0\n"
           "1.5,-0.0025,0,0.0829,1,0,0,0\n2.4,0.002,0,0.0829,1,0,0,0\n3,0.002,0,0.1,1,0,0,0\n";
  }
  SessionOptions o;
  o.scenario = std::string(ACDR_SOURCE_DIR) + "/scenarios/modules/02_c4c5_healthy.json";
  o.input = "replay:" + scoop;
  o.trainee = "t-c4c5";
  o.override_lock = true;  // module 01 is not mastered: an instructor's decision
  o.override_by = "instructor";
  o.override_reason = "layout test";
  o.db = path;
  o.quiet = true;
  std::ostringstream notes;
  const SessionResult run = run_attempt_session(o, nullptr, notes);
  ASSERT_EQ(run.end, SessionEnd::kCompleted) << run.error << notes.str();

  Database db = test::open_or_fail(path);
  auto model = load_dashboard(db);
  ASSERT_TRUE(model) << model.error().message;
  ASSERT_EQ(model->modules.size(), 4u);  // the curriculum, from the module's folder
  DashboardSelection sel;
  sel.trainee_id = "t-c4c5";
  sel.module_id = model->trainees.front().attempts.front().module_id;
  sel.attempt_id = run.attempt_id;
  sel.replay_t_s = 2.0;
  std::string error;
  auto attempt = load_drill_down(db, sel.attempt_id, &error);
  ASSERT_TRUE(attempt) << error;
  ASSERT_TRUE(attempt->bone_stress) << attempt->bone_stress_note;

  const int w = 1280, h = 800;
  auto ui = ImGuiOffscreen::create(w, h, &error);
  ASSERT_TRUE(ui) << error;
  std::vector<std::string> problems;
  std::vector<std::uint8_t> rgb;
  ASSERT_TRUE(ui->render(
      nullptr,
      [&] {
        draw_dashboard(*model, sel, attempt.get(), "", ImVec2(w, h), nullptr);
        problems = test::text_overflows(ImVec2(w, h));
        for (std::string& p :
             test::hidden_panes(ImVec2(w, h), {"metrics", "plots", "replay", "bone stress"}))
          problems.push_back(std::move(p));
      },
      &rgb, &error))
      << error;
  ASSERT_TRUE(write_png_rgb("dashboard_c4c5_1280x800.png", w, h, rgb, &error)) << error;
  for (const std::string& p : problems) ADD_FAILURE() << p;
}

// The probe itself sees a cut label: a long line in a narrow fixed window, a long cell in a
// narrow column, a window past the display's edge.
TEST(DashboardView, TheFitProbeSeesCutLabels) {
  std::string error;
  auto ui = ImGuiOffscreen::create(400, 300, &error);
  ASSERT_TRUE(ui) << error;
  std::vector<std::string> overflows, hidden;
  std::vector<std::uint8_t> rgb;
  ASSERT_TRUE(ui->render(
      nullptr,
      [&] {
        ImGui::SetNextWindowPos(ImVec2(10, 10));
        ImGui::SetNextWindowSize(ImVec2(120, 80));
        ImGui::Begin("narrow", nullptr, ImGuiWindowFlags_NoResize);
        ImGui::TextUnformatted("Zone.vertebral artery left.peak force");
        ImGui::End();
        ImGui::SetNextWindowPos(ImVec2(10, 120));
        ImGui::SetNextWindowSize(ImVec2(300, 100));
        ImGui::Begin("table", nullptr, ImGuiWindowFlags_NoResize);
        if (ImGui::BeginTable("t", 2, ImGuiTableFlags_SizingStretchSame)) {
          ImGui::TableNextRow();
          ImGui::TableNextColumn();
          ImGui::TextUnformatted("Peak shaft bending moment (N·m)");
          ImGui::TableNextColumn();
          ImGui::TextUnformatted("1");
          ImGui::EndTable();
        }
        ImGui::End();
        ImGui::SetNextWindowPos(ImVec2(350, 250));
        ImGui::Begin("past the edge", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
        ImGui::TextUnformatted("withdraw now");
        ImGui::End();
        // Two panes in a short scrolling window: the first shows, the second is below the fold.
        ImGui::SetNextWindowPos(ImVec2(150, 10));
        ImGui::SetNextWindowSize(ImVec2(180, 100));
        ImGui::Begin("short", nullptr, ImGuiWindowFlags_NoResize);
        ImGui::BeginChild("shown", ImVec2(0, 30));
        ImGui::EndChild();
        ImGui::BeginChild("below the fold", ImVec2(0, 60));
        ImGui::EndChild();
        ImGui::End();
        overflows = test::text_overflows(ImVec2(400, 300));
        hidden = test::hidden_panes(ImVec2(400, 300), {"shown", "below the fold", "absent"});
      },
      &rgb, &error))
      << error;
  auto said = [&](const std::string& what) {
    for (const std::string& o : overflows)
      if (o.find(what) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(said("window 'narrow': text needs")) << overflows.size();
  EXPECT_TRUE(said("table in 'table', column 0: a cell needs")) << overflows.size();
  EXPECT_TRUE(said("window 'past the edge' reaches outside the display")) << overflows.size();
  ASSERT_EQ(hidden.size(), 2u);
  EXPECT_NE(hidden[0].find("pane 'below the fold'"), std::string::npos) << hidden[0];
  EXPECT_NE(hidden[0].find("is not all shown by 'short'"), std::string::npos) << hidden[0];
  EXPECT_EQ(hidden[1], "pane 'absent' is not drawn");
}

}  // namespace
}  // namespace acdr
