// Tests of ui/dashboard_view at the size of a common laptop screen, 1280 x 800: every text the
// dashboard lays out fits its pane, column or window (text_fit_probe.hpp measures each against
// the width it was given), metric rows read as words with units, and the picture is kept as
// dashboard_1280x800.png in the working directory for a person to look at.
#include "ui/dashboard_view.hpp"

#include <gtest/gtest.h>

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

// The probe itself sees a cut label: a long line in a narrow fixed window, a long cell in a
// narrow column, a window past the display's edge.
TEST(DashboardView, TheFitProbeSeesCutLabels) {
  std::string error;
  auto ui = ImGuiOffscreen::create(400, 300, &error);
  ASSERT_TRUE(ui) << error;
  std::vector<std::string> overflows;
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
        overflows = test::text_overflows(ImVec2(400, 300));
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
}

}  // namespace
}  // namespace acdr
