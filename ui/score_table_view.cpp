// The score table's ImGui layout.
#include "ui/score_table_view.hpp"

#include <imgui.h>

#include "ui/imgui_style.hpp"

namespace acdr {

void draw_score_table(const char* id, const std::vector<ScoreTableRow>& rows) {
  if (!ImGui::BeginTable(id, 4,
                         ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg |
                             ImGuiTableFlags_SizingStretchProp))
    return;
  ImGui::TableSetupColumn("Metric", ImGuiTableColumnFlags_WidthStretch, 2.2f);
  ImGui::TableSetupColumn("Value", ImGuiTableColumnFlags_WidthStretch, 0.8f);
  ImGui::TableSetupColumn("Benchmark", ImGuiTableColumnFlags_WidthStretch, 2.2f);
  ImGui::TableSetupColumn("Score", ImGuiTableColumnFlags_WidthStretch, 0.7f);
  ImGui::TableHeadersRow();
  for (const ScoreTableRow& r : rows) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    switch (r.judgement) {
      case MetricJudgement::kScored:
        if (r.safety)
          ImGui::Text("Safety: %s", r.label.c_str());
        else
          ImGui::TextUnformatted(r.label.c_str());
        break;
      case MetricJudgement::kGated: ImGui::Text("Gate: %s", r.label.c_str()); break;
      case MetricJudgement::kNotAssessed:
        ImGui::TextColored(ui_colors::kMuted, "%s", r.label.c_str());
        break;
    }
    ImGui::TableNextColumn();
    ImGui::Text("%.4g", r.value);
    ImGui::TableNextColumn();
    const std::string benchmark = benchmark_text(r);
    if (r.judgement == MetricJudgement::kScored && !r.benchmark)
      ImGui::TextColored(ui_colors::kMuted, "%s", benchmark.c_str());
    else
      ImGui::TextUnformatted(benchmark.c_str());
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
