// The score table's ImGui layout.
#include "ui/score_table_view.hpp"

#include <cstdio>

#include <imgui.h>

#include "ui/imgui_style.hpp"
#include "ui/word_wrap.hpp"

namespace acdr {
namespace {

// Text that wraps at its table cell's right edge, so a narrow pane never cuts a label.
void cell_text(const ImVec4* color, const std::string& text) {
  ImGui::PushTextWrapPos(0.0f);
  if (color) ImGui::PushStyleColor(ImGuiCol_Text, *color);
  text_wrapped("%s", text.c_str());
  if (color) ImGui::PopStyleColor();
  ImGui::PopTextWrapPos();
}

}  // namespace

void draw_score_table(const char* id, const std::vector<ScoreTableRow>& rows) {
  if (!ImGui::BeginTable(id, 4,
                         ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg |
                             ImGuiTableFlags_SizingStretchProp))
    return;
  // The value and score columns as wide as their widest text; the words share the rest.
  const float value_w = ImGui::CalcTextSize("-0.0000e-00").x;
  const float score_w = ImGui::CalcTextSize("FAILED").x;
  ImGui::TableSetupColumn("Metric", ImGuiTableColumnFlags_WidthStretch, 1.3f);
  ImGui::TableSetupColumn("Value", ImGuiTableColumnFlags_WidthFixed, value_w);
  ImGui::TableSetupColumn("Benchmark", ImGuiTableColumnFlags_WidthStretch, 1.0f);
  ImGui::TableSetupColumn("Score", ImGuiTableColumnFlags_WidthFixed, score_w);
  ImGui::TableHeadersRow();
  for (const ScoreTableRow& r : rows) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    switch (r.judgement) {
      case MetricJudgement::kScored:
        cell_text(nullptr, r.safety ? "Safety: " + r.label : r.label);
        break;
      case MetricJudgement::kGated: cell_text(nullptr, "Gate: " + r.label); break;
      case MetricJudgement::kNotAssessed: cell_text(&ui_colors::kMuted, r.label); break;
    }
    ImGui::TableNextColumn();
    if (r.measured)
      ImGui::Text("%.4g", r.value);
    else
      ImGui::TextColored(ui_colors::kMuted, "none");
    ImGui::TableNextColumn();
    const std::string benchmark = benchmark_text(r);
    cell_text(r.judgement == MetricJudgement::kScored && !r.benchmark ? &ui_colors::kMuted
                                                                       : nullptr,
              benchmark);
    ImGui::TableNextColumn();
    if (r.judgement == MetricJudgement::kScored)
      ImGui::TextColored(r.good ? ui_colors::kOk : ui_colors::kWarning, "%.0f", r.score);
    else if (r.judgement == MetricJudgement::kGated)
      ImGui::TextColored(r.good ? ui_colors::kOk : ui_colors::kDanger, "%s",
                         r.good ? "held" : "FAILED");
  }
  ImGui::EndTable();
}

}  // namespace acdr
