// Tests of ui/score_table_view: the table drawn offscreen shows each verdict in its state
// colour (a weak score amber, a good one green, a failed gate red) and nothing red when every
// row is fine.
#include "ui/score_table_view.hpp"

#include <gtest/gtest.h>
#include <imgui.h>

#include "tests/ui/image_probe.hpp"
#include "ui/imgui_offscreen.hpp"

namespace acdr {
namespace {

using test::Image;
using test::Rgb;

bool is_red(const Rgb& c) { return c.r > 190 && c.g < 100 && c.b < 100; }
bool is_amber(const Rgb& c) { return c.r > 200 && c.g > 130 && c.g < 200 && c.b < 90; }
bool is_green(const Rgb& c) { return c.g > 150 && c.g > c.r + 40 && c.g > c.b + 40; }

Image draw(const std::vector<ScoreTableRow>& rows) {
  const int w = 700, h = 240;
  std::string error;
  auto ui = ImGuiOffscreen::create(w, h, &error);
  EXPECT_TRUE(ui) << error;
  Image im{w, h, {}};
  if (!ui) return im;
  EXPECT_TRUE(ui->render(
      nullptr,
      [&] {
        ImGui::SetNextWindowPos(ImVec2(0, 0));
        ImGui::SetNextWindowSize(ImVec2(w, h));
        ImGui::Begin("table");
        draw_score_table("metrics", rows);
        ImGui::End();
      },
      &im.rgb, &error))
      << error;
  return im;
}

std::vector<ScoreTableRow> rows(bool all_good) {
  Metrics metrics;
  ScoreResult score;
  score.terms = {{"nucleus_removed_fraction", 0.05, all_good ? 80.0 : 30.0},
                 {"peak_instrument_force_N", 1.0, 60.0}};
  score.gates = {{"overload_events", all_good ? 0.0 : 2.0, 0.0, all_good}};
  Rubric rubric;
  rubric.terms.push_back({"nucleus_removed_fraction", 0.15, 0.05, true, 1.0});
  return score_table(metrics, score, &rubric, ScoreTableScope::kAssessed);
}

TEST(ScoreTableView, VerdictsShowInTheirStateColours) {
  const Image failing = draw(rows(false));
  EXPECT_GT(failing.fraction(is_red), 0.0003);    // FAILED
  EXPECT_GT(failing.fraction(is_amber), 0.0001);  // the weak score
  EXPECT_GT(failing.fraction(is_green), 0.0001);  // the good score
  const Image passing = draw(rows(true));
  EXPECT_EQ(passing.fraction(is_red), 0.0);
  EXPECT_GT(passing.fraction(is_green), failing.fraction(is_green));  // and "held"
}

}  // namespace
}  // namespace acdr
