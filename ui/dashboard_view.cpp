// The dashboard's ImGui layout.
#include "ui/dashboard_view.hpp"

#include "ui/bone_stress_pane.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <imgui_internal.h>  // BeginComboPreview: the chooser's preview laid out as text

#include "ui/imgui_style.hpp"
#include "ui/plot_widgets.hpp"
#include "ui/score_table_view.hpp"
#include "ui/trainee_hud.hpp"
#include "ui/word_wrap.hpp"

namespace acdr {
namespace {

ImU32 u32(const ImVec4& c, float alpha = 1.0f) {
  return ImGui::ColorConvertFloat4ToU32(ImVec4(c.x, c.y, c.z, c.w * alpha));
}

ImVec4 state_color(const std::string& state) {
  if (state == "mastered") return ui_colors::kMastered;
  if (state == "passed") return ui_colors::kOk;
  if (state == "in progress") return ui_colors::kWarning;
  if (state == "locked") return ui_colors::kLocked;
  return ImVec4(0.24f, 0.27f, 0.33f, 1.0f);  // not started
}

ImVec4 event_color(const std::string& kind) {
  if (kind == "overload_yield" || kind == "numerical" || kind == "device_disconnected")
    return ui_colors::kDanger;
  if (kind == "overload_warning") return ui_colors::kWarning;
  if (kind.find("zone") != std::string::npos) return ImVec4(0.95f, 0.45f, 0.15f, 1.0f);
  if (kind == "force_clamped") return ImVec4(0.75f, 0.50f, 0.95f, 1.0f);
  if (kind == "input_rejected" || kind == "input_lost") return ui_colors::kMuted;
  return ui_colors::kInfo;
}

std::string fmt(const char* f, double v) {
  char text[64];
  std::snprintf(text, sizeof text, f, v);
  return text;
}

// "2024-05-02T10:11:12Z" -> "05-02 10:11".
std::string short_time(const std::string& utc) {
  if (utc.size() >= 16) return utc.substr(5, 5) + " " + utc.substr(11, 5);
  return utc;
}

void section_title(const char* text) {
  ImGui::Spacing();
  ImGui::TextColored(ui_colors::kInfo, "%s", text);
  ImGui::Separator();
}

// ---- left: trainees ----------------------------------------------------------------------
void draw_trainee_list(const DashboardModel& model, DashboardSelection& sel,
                       DashboardActions* actions) {
  section_title("Trainees");
  for (const DashboardTrainee& t : model.trainees) {
    int mastered = 0;
    for (const ModuleProgress& p : t.progress) mastered += p.mastered;
    char label[200];
    std::snprintf(label, sizeof label, "%s%s%s\n  %zu %s, %d/%zu mastered",
                  t.info.id.c_str(), t.info.display_name.empty() ? "" : " - ",
                  t.info.display_name.c_str(), t.attempts.size(),
                  t.attempts.size() == 1 ? "attempt" : "attempts", mastered, t.progress.size());
    if (ImGui::Selectable(label, sel.trainee_id == t.info.id)) {
      if (sel.trainee_id != t.info.id) {
        sel.trainee_id = t.info.id;
        sel.attempt_id = 0;
        if (!t.attempts.empty()) sel.module_id = t.attempts.back().module_id;
        actions->attempt_changed = true;
      }
    }
  }
  if (model.trainees.empty()) ImGui::TextColored(ui_colors::kMuted, "No trainees yet.");
  ImGui::Spacing();
  ImGui::TextColored(ui_colors::kMuted, "Practice attempts: %zu", model.practice.size());
  ImGui::Spacing();
  if (ImGui::Button("Overview")) {
    sel = DashboardSelection{};
    actions->attempt_changed = true;
  }
  ImGui::SameLine();
  if (ImGui::Button("Refresh")) actions->refresh = true;
  if (ImGui::Button("Export CSV of this view")) actions->export_csv = true;
}

// ---- progress matrix -----------------------------------------------------------------------
void draw_progress_matrix(const DashboardModel& model, DashboardSelection& sel,
                          DashboardActions* actions) {
  section_title("Curriculum progress");
  if (model.modules.empty()) {
    ImGui::TextColored(ui_colors::kMuted, "No modules registered yet (run a module first).");
    return;
  }
  const int columns = 1 + static_cast<int>(model.modules.size());
  if (ImGui::BeginTable("progress", columns,
                        ImGuiTableFlags_Borders | ImGuiTableFlags_SizingStretchProp)) {
    // Each column stretches in proportion to its widest word (a header piece, a trainee id,
    // a state), so a column narrower than the table's share still shows "degenerated" whole
    // when the others can give it room.
    const auto measure = [](std::string_view s) {
      return ImGui::CalcTextSize(s.data(), s.data() + s.size()).x;
    };
    float trainee_width = measure("Trainee");
    for (const DashboardTrainee& t : model.trainees)
      trainee_width = std::max(trainee_width, measure(t.info.id));
    ImGui::TableSetupColumn("Trainee", ImGuiTableColumnFlags_WidthStretch, trainee_width);
    const float state_width = measure("in progress");
    for (const ModuleRecord& m : model.modules) {
      const std::string name = std::to_string(m.position) + ". " + m.id;
      ImGui::TableSetupColumn(name.c_str(), ImGuiTableColumnFlags_WidthStretch,
                              std::max(state_width, widest_piece(name, measure, "-")));
    }
    // The header row drawn as wrapped text: with four modules beside the learning curve a
    // column is narrower than "4. c4c5-full-discectomy", and a header row would cut it.
    ImGui::TableNextRow(ImGuiTableRowFlags_Headers);
    for (int c = 0; c < columns; ++c) {
      ImGui::TableSetColumnIndex(c);
      ImGui::TableSetBgColor(ImGuiTableBgTarget_CellBg, ImGui::GetColorU32(ImGuiCol_TableHeaderBg));
      // Module ids break after their hyphens, not inside a word ("c4c5-healt" / "hy").
      wrapped_label(ImGui::TableGetColumnName(c), "-");
    }
    for (const DashboardTrainee& t : model.trainees) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(t.info.id.c_str());
      for (const ModuleRecord& m : model.modules) {
        ImGui::TableNextColumn();
        const ModuleProgress* p = nullptr;
        for (const ModuleProgress& q : t.progress)
          if (q.module_id == m.id) p = &q;
        if (!p) continue;
        const std::string state = progress_state(*p);
        ImGui::TableSetBgColor(ImGuiTableBgTarget_CellBg, u32(state_color(state), 0.55f));
        char cell[120];
        std::snprintf(cell, sizeof cell, "%s##%s-%s", state.c_str(), t.info.id.c_str(),
                      m.id.c_str());
        if (ImGui::Selectable(cell, sel.trainee_id == t.info.id && sel.module_id == m.id)) {
          sel.trainee_id = t.info.id;
          sel.module_id = m.id;
          sel.attempt_id = 0;
          actions->attempt_changed = true;
        }
        if (p->run.attempts > 0) {
          ImGui::PushStyleColor(ImGuiCol_Text, ui_colors::kMuted);
          text_wrapped("%d %s, run %d/%d", p->run.attempts, p->run.attempts == 1 ? "try" : "tries",
                       p->run.consecutive_at_end, p->required_consecutive);
          ImGui::PopStyleColor();
        }
      }
    }
    ImGui::EndTable();
  }
  // Legend.
  std::vector<LegendItem> states;
  for (const char* s : {"locked", "not started", "in progress", "passed", "mastered"})
    states.push_back({u32(state_color(s)), s});
  draw_legend(states);
}

// ---- learning curve --------------------------------------------------------------------------
const ModuleRecord* chosen_module(const DashboardModel& model, const DashboardSelection& sel) {
  const ModuleRecord* module = model.find_module(sel.module_id);
  if (!module && !model.modules.empty()) module = &model.modules.front();
  return module;
}

void draw_learning_curve(const DashboardModel& model, const DashboardTrainee& t,
                         DashboardSelection& sel, DashboardActions* actions) {
  section_title(("Learning curve: " + t.info.id).c_str());
  const ModuleRecord* module = chosen_module(model, sel);
  if (!module) return;
  // Module chooser, as wide as the column allows beside its label. The preview is laid out
  // as text inside the box (not clipped by the box silently), so a preview that does not fit
  // shows as cut text to the layout tests; the list shows each module's id and title.
  const char* label = "Module";
  ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - ImGui::CalcTextSize(label).x -
                          ImGui::GetStyle().ItemInnerSpacing.x);
  if (ImGui::BeginCombo(label, nullptr, ImGuiComboFlags_CustomPreview)) {
    for (const ModuleRecord& m : model.modules)
      if (ImGui::Selectable((std::to_string(m.position) + ". " + m.id + ": " + m.title).c_str(),
                            m.id == module->id)) {
        sel.module_id = m.id;
        sel.attempt_id = 0;
        actions->attempt_changed = true;
      }
    ImGui::EndCombo();
  }
  if (ImGui::BeginComboPreview()) {
    ImGui::TextUnformatted((std::to_string(module->position) + ". " + module->id).c_str());
    ImGui::EndComboPreview();
  }
  const auto attempts = curve_attempts(t, module->id);
  std::vector<float> xs, ys;
  std::vector<ImU32> colors;
  for (std::size_t i = 0; i < attempts.size(); ++i) {
    if (!attempts[i]->score) continue;  // aborted: no score
    xs.push_back(static_cast<float>(i + 1));
    ys.push_back(static_cast<float>(*attempts[i]->score));
    colors.push_back(u32(attempts[i]->passed.value_or(false) ? ui_colors::kOk
                                                              : ui_colors::kDanger));
  }
  PlotOptions o;
  o.id = "curve";
  o.size = ImVec2(-1, 110);
  o.x_min = 0.5f;
  o.x_max = static_cast<float>(std::max<std::size_t>(attempts.size(), 2)) + 0.5f;
  o.y_min = 0;
  o.y_max = 105;
  o.x_label = "attempt";
  o.y_label = "score";
  o.integer_x = true;
  PlotSeries s;
  s.x = xs;
  s.y = ys;
  s.color = u32(ui_colors::kInfo);
  s.markers = true;
  s.point_colors = colors;
  s.label = "score";
  const PlotLine pass{static_cast<float>(module->pass_score), u32(ui_colors::kOk, 0.8f),
                      "pass " + fmt("%.0f", module->pass_score)};
  const std::array<PlotSeries, 1> series{s};
  const std::array<PlotLine, 1> lines{pass};
  draw_plot(o, series, lines);
}

// The progression rule's state at the chosen module and its attempts, selectable for the
// drill-down.
void draw_attempt_list(const DashboardModel& model, const DashboardTrainee& t,
                       DashboardSelection& sel, DashboardActions* actions) {
  const ModuleRecord* module = chosen_module(model, sel);
  if (!module) return;
  section_title(("Attempts at " + module->id).c_str());
  const auto attempts = curve_attempts(t, module->id);
  ImGui::PushTextWrapPos(0.0f);
  for (const ModuleProgress& p : t.progress) {
    if (p.module_id != module->id) continue;
    const std::string state = progress_state(p);
    ImGui::TextColored(state_color(state), "%s", state.c_str());
    ImGui::SameLine();
    if (p.mastered) {
      ImGui::Text("- mastered at attempt %d (%d passes in a row needed)", p.run.mastered_at,
                  p.required_consecutive);
    } else if (!p.unlocked) {
      std::string missing;
      for (const std::string& m : p.missing_prerequisites) missing += (missing.empty() ? "" : ", ") + m;
      ImGui::Text("- needs %s mastered first", missing.c_str());
    } else {
      ImGui::Text("- %d of %d passing attempts in a row (score >= %.0f); %d attempts, %d passed",
                  p.run.consecutive_at_end, p.required_consecutive, p.pass_score,
                  p.run.attempts, p.run.passes);
    }
  }
  ImGui::PopTextWrapPos();

  if (ImGui::BeginTable("attempts", 5,
                        ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg |
                            ImGuiTableFlags_SizingStretchProp | ImGuiTableFlags_ScrollY,
                        ImVec2(0, std::min(130.0f, 26.0f + 40.0f * attempts.size())))) {
    ImGui::TableSetupScrollFreeze(0, 1);
    // The try's number and the record's id as narrow as their digits; the rest share the width
    // and wrap ("11-26" over "16:48", "not" over "passed") rather than being cut.
    const float digits = ImGui::CalcTextSize("999").x;
    ImGui::TableSetupColumn("#", ImGuiTableColumnFlags_WidthFixed, digits);
    ImGui::TableSetupColumn("id", ImGuiTableColumnFlags_WidthFixed, digits);
    ImGui::TableSetupColumn("started", ImGuiTableColumnFlags_WidthStretch, 1.0f);
    ImGui::TableSetupColumn("score", ImGuiTableColumnFlags_WidthStretch, 0.8f);
    ImGui::TableSetupColumn("result", ImGuiTableColumnFlags_WidthStretch, 1.1f);
    ImGui::TableHeadersRow();
    ImGui::PushTextWrapPos(0.0f);
    for (std::size_t i = 0; i < attempts.size(); ++i) {
      const AttemptRecord& a = *attempts[i];
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      char label[32];
      std::snprintf(label, sizeof label, "%zu", i + 1);
      if (ImGui::Selectable(label, sel.attempt_id == a.id, ImGuiSelectableFlags_SpanAllColumns)) {
        sel.attempt_id = a.id;
        sel.replay_t_s = 0;
        actions->attempt_changed = true;
      }
      ImGui::TableNextColumn();
      ImGui::Text("%lld", static_cast<long long>(a.id));
      ImGui::TableNextColumn();
      text_wrapped("%s", short_time(a.started_utc).c_str());
      ImGui::TableNextColumn();
      if (a.score) ImGui::Text("%.1f", *a.score);
      ImGui::TableNextColumn();
      // passed / not passed for a completed attempt, else its status (aborted, running).
      ImGui::PushStyleColor(ImGuiCol_Text, !a.passed  ? ui_colors::kMuted
                                           : *a.passed ? ui_colors::kOk
                                                       : ui_colors::kDanger);
      text_wrapped("%s", !a.passed   ? attempt_status_name(a.status)
                               : *a.passed ? "passed"
                                           : "not passed");
      ImGui::PopStyleColor();
    }
    ImGui::PopTextWrapPos();
    ImGui::EndTable();
  }
}

// ---- drill-down pieces -----------------------------------------------------------------------
void draw_metrics_table(const AttemptDrillDown& d) {
  ImGui::TextUnformatted("Metrics against benchmarks");
  draw_score_table("metrics", d.metric_rows);
  ImGui::PushTextWrapPos(0.0f);
  for (const std::string& z : d.zone_findings)
    text_colored_wrapped(ui_colors::kDanger, "- Zones: %s", z.c_str());
  for (const std::string& r : d.record.score_detail.reasons)
    text_colored_wrapped(ui_colors::kWarning, "- %s", r.c_str());
  if (ImGui::TreeNode("How to read the scores")) {
    ImGui::TextColored(ui_colors::kMuted, "50 = the experts' mean, 10 points per expert SD.");
    for (const std::string& line : d.scale) text_colored_wrapped(ui_colors::kMuted, "%s", line.c_str());
    ImGui::TreePop();
  }
  ImGui::PopTextWrapPos();
}

void draw_event_timeline(const AttemptDrillDown& d, DashboardSelection& sel) {
  ImGui::TextUnformatted("Events");
  // A strip: one tick per event at its time, coloured by kind; click to jump the replay.
  const float width = ImGui::GetContentRegionAvail().x;
  const ImVec2 a = ImGui::GetCursorScreenPos();
  const ImVec2 b(a.x + width, a.y + 26);
  ImGui::InvisibleButton("timeline", ImVec2(width, 26));
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddRectFilled(a, b, IM_COL32(22, 24, 28, 255));
  const double duration = std::max(d.duration_s, 1e-3);
  for (const EventRecord& e : d.record.events) {
    const float x = a.x + static_cast<float>(e.t_s / duration) * width;
    dl->AddLine(ImVec2(x, a.y + 3), ImVec2(x, b.y - 3), u32(event_color(e.kind)), 3.0f);
  }
  const float cx = a.x + static_cast<float>(sel.replay_t_s / duration) * width;
  dl->AddLine(ImVec2(cx, a.y), ImVec2(cx, b.y), IM_COL32(255, 255, 255, 220), 1.5f);
  if (ImGui::IsItemActive())
    sel.replay_t_s = std::clamp((ImGui::GetIO().MousePos.x - a.x) / width, 0.0f, 1.0f) * duration;

  if (ImGui::BeginTable("events", 4,
                        ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg |
                            ImGuiTableFlags_ScrollY | ImGuiTableFlags_SizingStretchProp,
                        ImVec2(0, 130))) {
    ImGui::TableSetupScrollFreeze(0, 1);
    ImGui::TableSetupColumn("t (s)", ImGuiTableColumnFlags_WidthStretch, 0.5f);
    ImGui::TableSetupColumn("event", ImGuiTableColumnFlags_WidthStretch, 1.1f);
    ImGui::TableSetupColumn("value", ImGuiTableColumnFlags_WidthStretch, 0.6f);
    ImGui::TableSetupColumn("detail", ImGuiTableColumnFlags_WidthStretch, 1.8f);
    ImGui::TableHeadersRow();
    for (std::size_t i = 0; i < d.record.events.size(); ++i) {
      const EventRecord& e = d.record.events[i];
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      char label[32];
      std::snprintf(label, sizeof label, "%.3f##ev%zu", e.t_s, i);
      if (ImGui::Selectable(label, false, ImGuiSelectableFlags_SpanAllColumns))
        sel.replay_t_s = e.t_s;
      ImGui::TableNextColumn();
      ImGui::TextColored(event_color(e.kind), "%s%s%s", e.kind.c_str(),
                         e.zone.empty() ? "" : " @ ", e.zone.c_str());
      ImGui::TableNextColumn();
      ImGui::Text("%.4g", e.value);
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(e.detail.c_str());
    }
    ImGui::EndTable();
  }
}

std::vector<PlotBand> bands_of(const std::vector<TimeBand>& in, ImU32 color) {
  std::vector<PlotBand> out;
  for (const TimeBand& b : in)
    out.push_back({static_cast<float>(b.t0_s), static_cast<float>(b.t1_s), color});
  return out;
}

void draw_time_plots(const AttemptDrillDown& d, DashboardSelection& sel) {
  const AttemptRecording& r = *d.recording;
  const float cursor = static_cast<float>(sel.replay_t_s);
  // Force over time with overload (amber, red) and rejected-input (grey) bands.
  std::vector<PlotBand> bands = bands_of(d.input_invalid, IM_COL32(150, 150, 150, 50));
  for (const PlotBand& b : bands_of(d.zone_warning, IM_COL32(242, 115, 38, 45))) bands.push_back(b);
  for (const PlotBand& b : bands_of(d.zone_inside, IM_COL32(240, 40, 150, 70))) bands.push_back(b);
  for (const PlotBand& b : bands_of(d.overload_warning, u32(ui_colors::kWarning, 0.25f)))
    bands.push_back(b);
  for (const PlotBand& b : bands_of(d.overload_yield, u32(ui_colors::kDanger, 0.35f)))
    bands.push_back(b);
  PlotOptions force;
  force.id = "force";
  force.title = "Force over time";
  force.size = ImVec2(-1, 130);
  force.x_min = 0;
  force.x_max = static_cast<float>(std::max(d.duration_s, 1e-3));
  force.x_label = "time (s)";
  force.y_label = "N";
  force.cursor_x = cursor;
  const PlotSeries hand = line_series(d.t_s, d.hand_force_N, u32(ui_colors::kInfo), "on the hand");
  const PlotSeries tissue = line_series(d.t_s, d.tissue_force_N, IM_COL32(235, 200, 120, 255), "on tissue/walls");
  const std::array<PlotSeries, 2> fs{hand, tissue};
  const std::array<PlotLine, 1> limit{
      PlotLine{static_cast<float>(r.summary.device_max_force_N), u32(ui_colors::kDanger, 0.8f),
               "device max " + fmt("%.1f N", r.summary.device_max_force_N)}};
  PlotInteraction pi = draw_plot(force, fs, limit, bands);
  // What the bands behind the curves mean, in their colours.
  ImGui::TextColored(ui_colors::kMuted, "Bands:");
  const std::array<LegendItem, 5> band_legend{
      LegendItem{u32(ui_colors::kWarning, 0.6f), "overload warning"},
      LegendItem{u32(ui_colors::kDanger, 0.7f), "above yield"},
      LegendItem{IM_COL32(242, 115, 38, 160), "near a danger zone"},
      LegendItem{IM_COL32(240, 40, 150, 200), "inside one"},
      LegendItem{IM_COL32(150, 150, 150, 160), "input rejected or lost"}};
  draw_legend(band_legend, true);
  if (pi.clicked) sel.replay_t_s = pi.x_at_mouse;

  // Shaft bending moment against its warning and yield.
  PlotOptions moment = force;
  moment.id = "moment";
  moment.title = "Shaft bending moment";
  moment.size = ImVec2(-1, 100);
  moment.y_label = "N·m";
  const PlotSeries m = line_series(d.t_s, d.moment_Nm, IM_COL32(200, 160, 255, 255), "moment");
  const std::array<PlotSeries, 1> ms{m};
  const std::array<PlotLine, 2> moment_lines{
      PlotLine{static_cast<float>(r.summary.warning_moment_Nm), u32(ui_colors::kWarning),
               "warning"},
      PlotLine{static_cast<float>(r.summary.yield_moment_Nm), u32(ui_colors::kDanger), "yield"}};
  pi = draw_plot(moment, ms, moment_lines, bands);
  if (pi.clicked) sel.replay_t_s = pi.x_at_mouse;
}

// The recorded instrument in two projections (top: x-y, side: x-z), the box, and the tip
// path so far coloured by the force on the hand.
void draw_replay(const AttemptDrillDown& d, DashboardSelection& sel) {
  const AttemptRecording& r = *d.recording;
  const float duration = static_cast<float>(std::max(d.duration_s, 1e-3));
  ImGui::TextUnformatted("Replay");
  ImGui::SetNextItemWidth(-1);
  float t = static_cast<float>(sel.replay_t_s);
  if (ImGui::SliderFloat("##time", &t, 0.0f, duration, "t = %.2f s")) sel.replay_t_s = t;
  const std::size_t i = d.frame_at(sel.replay_t_s);
  const Frame& f = r.frames[i];
  ImGui::PushStyleColor(ImGuiCol_Text, ui_colors::kMuted);
  text_wrapped(
      "The instrument and its tip path (colour: force on the hand); particles are not "
      "recorded.");
  ImGui::PopStyleColor();
  text_wrapped("removed %.1f %%   hand %.2f N   tissue %.2f N   moment %.3f N·m",
                     100.0 * d.removed_fraction[i], d.hand_force_N[i], d.tissue_force_N[i],
                     f.bending_moment_Nm);

  if (!d.replay.bone_note.empty()) ImGui::TextColored(ui_colors::kMuted, "%s", d.replay.bone_note.c_str());
  // Geometry from the model (box walls, the instrument at this frame's grip pose) and what is
  // drawn: the walls, the whole tip path and the instrument's working end now.
  const std::vector<Collider>& statics = d.replay.walls;
  std::vector<Collider> instrument;
  d.replay.instrument_at(f.instrument, f.t_s, instrument);
  Eigen::AlignedBox3d box = d.replay.bounds;
  box.extend(f.tip_m + (f.instrument.position - f.tip_m) * 0.35);
  if (box.isEmpty()) return;
  const Vec3 pad = Vec3::Constant(2e-3);
  box.extend(box.min() - pad);
  box.extend(box.max() + pad);

  const float panel_w = (ImGui::GetContentRegionAvail().x - 10.0f) * 0.5f;
  // The panels take the height left in the pane (under their titles), up to a square-ish shape.
  const float panel_h = std::clamp(
      ImGui::GetContentRegionAvail().y - ImGui::GetTextLineHeightWithSpacing() - 2.0f, 60.0f,
      std::min(170.0f, panel_w * 0.9f));
  const double device_max = std::max(r.summary.device_max_force_N, 1e-6);
  for (int view = 0; view < 2; ++view) {
    if (view == 1) ImGui::SameLine(0, 10);
    const int ax = 0, ay = view == 0 ? 1 : 2;  // top: x-y, side: x-z
    ImGui::BeginGroup();
    const MeshSilhouette& bone = view == 0 ? d.replay.bone_top : d.replay.bone_side;
    // With vertebrae, name the views as a surgeon would: from above is the anterior view.
    const char* title = bone.empty() ? (view == 0 ? "Top (x-y)" : "Side (x-z)")
                                     : (view == 0 ? "Front (x-y)"
                                                  : "Axial (x-z)");
    ImGui::TextColored(ui_colors::kMuted, "%s", title);
    const ImVec2 a = ImGui::GetCursorScreenPos();
    const ImVec2 b(a.x + panel_w, a.y + panel_h);
    ImGui::Dummy(ImVec2(panel_w, panel_h));
    ImGui::EndGroup();
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->AddRectFilled(a, b, IM_COL32(22, 24, 28, 255));
    dl->PushClipRect(a, b, true);
    const double span_x = box.max()[ax] - box.min()[ax], span_y = box.max()[ay] - box.min()[ay];
    const double scale = std::min((panel_w - 10) / span_x, (panel_h - 10) / span_y);
    const ImVec2 centre((a.x + b.x) * 0.5f, (a.y + b.y) * 0.5f);
    const Vec3 mid = box.center();
    auto project = [&](const Vec3& p) {
      return ImVec2(centre.x + static_cast<float>((p[ax] - mid[ax]) * scale),
                    centre.y - static_cast<float>((p[ay] - mid[ay]) * scale));
    };
    auto draw_box = [&](const Collider& c, ImU32 color) {
      std::array<ImVec2, 8> q;
      for (int k = 0; k < 8; ++k)
        q[k] = project(c.pose.apply(Vec3((k & 1 ? 1 : -1) * c.half_extents_m.x(),
                                         (k & 2 ? 1 : -1) * c.half_extents_m.y(),
                                         (k & 4 ? 1 : -1) * c.half_extents_m.z())));
      for (int k = 0; k < 8; ++k)
        for (int bit : {1, 2, 4})
          if (!(k & bit)) dl->AddLine(q[k], q[k | bit], color, 1.2f);
    };
    // The vertebrae's outline, then the walls (the tray for removed material).
    for (const MeshSilhouette::Run& run : bone.runs) {
      Vec3 p0 = Vec3::Zero(), p1 = Vec3::Zero();
      p0[ax] = bone.origin_a + run.first * bone.cell_m;
      p1[ax] = bone.origin_a + (run.last + 1) * bone.cell_m;
      p0[ay] = bone.origin_b + run.row * bone.cell_m;
      p1[ay] = bone.origin_b + (run.row + 1) * bone.cell_m;
      const ImVec2 q0 = project(p0), q1 = project(p1);
      dl->AddRectFilled(ImVec2(std::min(q0.x, q1.x), std::min(q0.y, q1.y)),
                        ImVec2(std::max(q0.x, q1.x), std::max(q0.y, q1.y)), IM_COL32(214, 204, 176, 90));
    }
    for (const Collider& c : statics) draw_box(c, IM_COL32(120, 150, 200, 150));
    // Tip path up to now, coloured green -> amber -> red with the force on the hand.
    const std::size_t stride = std::max<std::size_t>(1, (i + 1) / 1500);
    ImVec2 prev = project(r.frames[0].tip_m);
    for (std::size_t k = stride; k <= i; k += stride) {
      const ImVec2 p = project(r.frames[k].tip_m);
      const float load = static_cast<float>(std::min(1.0, d.hand_force_N[k] / device_max));
      const ImVec4 c = load < 0.5f ? ImVec4(0.35f + load, 0.78f, 0.42f - 0.4f * load, 1.0f)
                                   : ImVec4(0.93f, 0.78f - 1.0f * (load - 0.5f), 0.22f, 1.0f);
      dl->AddLine(prev, p, u32(c), 2.0f);
      prev = p;
    }
    // The instrument now.
    const ImU32 steel = IM_COL32(205, 208, 215, 255);
    for (const Collider& c : instrument) {
      if (c.kind == ColliderKind::kBox) {
        draw_box(c, steel);
      } else if (c.kind == ColliderKind::kCapsule) {
        const ImVec2 p0 = project(c.pose.apply(Vec3(0, 0, -c.half_length_m)));
        const ImVec2 p1 = project(c.pose.apply(Vec3(0, 0, c.half_length_m)));
        dl->AddLine(p0, p1, steel, std::max(2.0f, static_cast<float>(2 * c.radius_m * scale)));
      } else if (c.kind == ColliderKind::kCupShell) {
        dl->AddCircle(project(c.pose.position), static_cast<float>(c.radius_m * scale), steel, 24,
                      2.0f);
      }
    }
    if (instrument.empty()) dl->AddLine(project(f.instrument.position), project(f.tip_m), steel, 3);
    dl->AddCircleFilled(project(f.tip_m), 4.0f, IM_COL32(255, 255, 255, 255));
    dl->PopClipRect();
    dl->AddRect(a, b, IM_COL32(90, 92, 98, 255));
  }

}

// Nucleus removed over time, with the replay cursor.
void draw_removed_plot(const AttemptDrillDown& d, DashboardSelection& sel) {
  const float duration = static_cast<float>(std::max(d.duration_s, 1e-3));
  PlotOptions removed;
  removed.id = "removed";
  removed.title = "Nucleus removed";
  removed.size = ImVec2(-1, 100);
  removed.x_min = 0;
  removed.x_max = duration;
  removed.y_min = 0;
  removed.y_label = "fraction";
  removed.cursor_x = static_cast<float>(sel.replay_t_s);
  const PlotSeries s = line_series(d.t_s, d.removed_fraction, u32(ui_colors::kOk), "removed");
  const std::array<PlotSeries, 1> rs{s};
  const PlotInteraction pi = draw_plot(removed, rs);
  if (pi.clicked) sel.replay_t_s = pi.x_at_mouse;
}

void draw_attempt(const AttemptDrillDown& d, DashboardSelection& sel) {
  const AttemptRecord& a = d.record;
  char title[200];
  std::snprintf(title, sizeof title, "Attempt %lld: %s, %s, %s", static_cast<long long>(a.id),
                a.module_id.c_str(), short_time(a.started_utc).c_str(),
                attempt_status_name(a.status));
  section_title(title);
  if (a.score)
    ImGui::Text("Score %.1f", *a.score);
  else
    ImGui::TextColored(ui_colors::kMuted, "No score (%s)", attempt_status_name(a.status));
  if (a.passed) {
    ImGui::SameLine();
    ImGui::TextColored(*a.passed ? ui_colors::kOk : ui_colors::kDanger, "%s",
                       *a.passed ? "PASSED" : "NOT PASSED");
  }
  ImGui::SameLine();
  ImGui::PushStyleColor(ImGuiCol_Text, ui_colors::kMuted);
  text_wrapped("  input %s, %.1f s, program %s, scenario %s", a.input_device.c_str(),
                     a.duration_s.value_or(0.0), a.program_version.c_str(),
                     a.scenario_hash.substr(0, 8).c_str());
  ImGui::PopStyleColor();
  // How fast the simulation ran: for a live input, what the trainee saw (slow motion below
  // 0.95x); for a replay, only the machine's speed.
  if (a.realtime_factor) {
    const bool live = a.input_device.rfind("replay:", 0) != 0;
    if (live && is_slow_motion(*a.realtime_factor))
      ImGui::TextColored(ui_colors::kWarning,
                         "Ran at %.2fx real time: the trainee saw slow motion.",
                         *a.realtime_factor);
    else
      ImGui::TextColored(ui_colors::kMuted, "Ran at %.2fx real time%s.", *a.realtime_factor,
                         live ? "" : " (a replay: the machine's speed)");
  } else {
    ImGui::TextColored(ui_colors::kMuted, "Real-time factor not recorded.");
  }
  if (a.override_lock)
    ImGui::TextColored(ui_colors::kWarning, "Locked module taken by override of %s: %s",
                       a.override_by.c_str(), a.override_reason.c_str());
  if (!a.abort_reason.empty())
    ImGui::TextColored(ui_colors::kWarning, "Aborted: %s", a.abort_reason.c_str());
  if (!d.scenario_error.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ui_colors::kMuted);
    text_wrapped("Benchmarks and box outline unavailable: %s", d.scenario_error.c_str());
    ImGui::PopStyleColor();
  }

  // Three columns filling what is left of the pane, so that everything shows at once on a
  // 1280 x 800 screen: the metrics and events (scrolling in their column), the plots over time
  // (scrolling in theirs), and the replay with the bone stress, which must fit as they are
  // (no scrollbar: the layout tests see it if they do not).
  const float body_h = std::max(ImGui::GetContentRegionAvail().y, 300.0f);
  if (ImGui::BeginTable("drill", 3, ImGuiTableFlags_SizingStretchProp, ImVec2(0, body_h))) {
    ImGui::TableSetupColumn("metrics", ImGuiTableColumnFlags_WidthStretch, 1.35f);
    ImGui::TableSetupColumn("plots", ImGuiTableColumnFlags_WidthStretch, 1.0f);
    ImGui::TableSetupColumn("replay", ImGuiTableColumnFlags_WidthStretch, 1.05f);
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    const float child_h = body_h - ImGui::GetStyle().CellPadding.y * 2.0f;
    // The scrollbars always there, so the width the text wraps to never changes under it.
    const ImGuiWindowFlags scrolling = ImGuiWindowFlags_AlwaysVerticalScrollbar;
    ImGui::BeginChild("metrics", ImVec2(0, child_h), false, scrolling);
    draw_metrics_table(d);
    ImGui::Spacing();
    if (d.recording) draw_event_timeline(d, sel);
    ImGui::EndChild();
    ImGui::TableNextColumn();
    ImGui::BeginChild("plots", ImVec2(0, child_h), false, scrolling);
    if (d.recording) {
      draw_time_plots(d, sel);
      draw_removed_plot(d, sel);
    } else {
      ImGui::PushStyleColor(ImGuiCol_Text, ui_colors::kWarning);
      text_wrapped("No replay: %s", d.recording_error.c_str());
      ImGui::PopStyleColor();
    }
    ImGui::EndChild();
    ImGui::TableNextColumn();
    const ImGuiWindowFlags fixed = ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse;
    if (d.recording) {
      const bool bone = d.bone_stress != nullptr;
      ImGui::BeginChild("replay", ImVec2(0, bone ? child_h * 0.55f : child_h), false, fixed);
      draw_replay(d, sel);
      ImGui::EndChild();
      if (bone) {
        ImGui::BeginChild("bone stress", ImVec2(0, 0), false, fixed);
        draw_bone_stress_pane(*d.bone_stress, &sel.replay_t_s);
        ImGui::EndChild();
      } else if (!d.bone_stress_note.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ui_colors::kMuted);
        text_wrapped("No bone stress: %s", d.bone_stress_note.c_str());
        ImGui::PopStyleColor();
      }
    }
    ImGui::EndTable();
  }
}

}  // namespace

void draw_dashboard(const DashboardModel& model, DashboardSelection& sel,
                    const AttemptDrillDown* attempt, const std::string& status,
                    const ImVec2& display, DashboardActions* actions) {
  DashboardActions ignored;
  if (!actions) actions = &ignored;
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(display);
  ImGui::Begin("ACDR Trainer - instructor dashboard", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                   ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings |
                   ImGuiWindowFlags_NoBringToFrontOnFocus);
  const float footer = ImGui::GetFrameHeightWithSpacing();
  ImGui::BeginChild("left", ImVec2(250, -footer), true);
  draw_trainee_list(model, sel, actions);
  ImGui::EndChild();
  ImGui::SameLine();
  ImGui::BeginChild("right", ImVec2(0, -footer), true);
  // Progress matrix, learning curve and the attempts at its module side by side, the
  // drill-down below at full width.
  if (ImGui::BeginTable("top", 3, ImGuiTableFlags_SizingStretchProp)) {
    ImGui::TableSetupColumn("matrix", ImGuiTableColumnFlags_WidthStretch, 1.45f);
    ImGui::TableSetupColumn("curve", ImGuiTableColumnFlags_WidthStretch, 0.8f);
    ImGui::TableSetupColumn("attempts", ImGuiTableColumnFlags_WidthStretch, 1.0f);
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    draw_progress_matrix(model, sel, actions);
    ImGui::TableNextColumn();
    const DashboardTrainee* t = model.find_trainee(sel.trainee_id);
    if (t) {
      draw_learning_curve(model, *t, sel, actions);
    } else {
      ImGui::PushStyleColor(ImGuiCol_Text, ui_colors::kMuted);
      text_wrapped("Select a trainee for the learning curve.");
      ImGui::PopStyleColor();
    }
    ImGui::TableNextColumn();
    if (t) draw_attempt_list(model, *t, sel, actions);
    ImGui::EndTable();
  }
  if (attempt && attempt->record.id == sel.attempt_id) draw_attempt(*attempt, sel);
  ImGui::EndChild();
  ImGui::TextColored(ui_colors::kMuted, "%s   %s", model.db_path.c_str(), status.c_str());
  ImGui::End();
}

}  // namespace acdr
