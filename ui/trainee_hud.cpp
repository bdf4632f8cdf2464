// Trainee HUD and score screen.
#include "ui/trainee_hud.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "assessment/metric_labels.hpp"
#include "assessment/zone_findings.hpp"
#include "ui/imgui_style.hpp"
#include "ui/score_table_view.hpp"
#include "ui/word_wrap.hpp"

namespace acdr {
namespace {

ImU32 color_u32(const ImVec4& c) { return ImGui::ColorConvertFloat4ToU32(c); }

// At most this many alert lines: more would hide the scene.
constexpr std::size_t kMaxHudAlerts = 6;

const ImVec4& level_color(AlertLevel level) {
  switch (level) {
    case AlertLevel::kDanger: return ui_colors::kDanger;
    case AlertLevel::kWarning: return ui_colors::kWarning;
    case AlertLevel::kInfo: break;
  }
  return ui_colors::kInfo;
}

std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0) {
  char text[256];
  std::snprintf(text, sizeof text, fmt, a, b, c);
  return text;
}

// An alert for a recent event that is not about a zone, or none (empty text).
HudAlert alert_for_event(const Event& e) {
  switch (e.kind) {
    case EventKind::kOverloadYield:
      return {AlertLevel::kDanger, "Instrument overloaded: the shaft bent (" +
                                       format("%.3f N·m", e.value) + ")"};
    case EventKind::kOverloadWarning:
      return {AlertLevel::kWarning, "Shaft overload warning: lever more gently"};
    case EventKind::kForceClamped:
      return {AlertLevel::kWarning, "Force limited to the device maximum (" +
                                        format("%.1f N asked", e.value) + ")"};
    case EventKind::kInputRejected:
      return {AlertLevel::kWarning, "Device input rejected (" + e.detail + "): holding"};
    case EventKind::kInputLost:
      return {AlertLevel::kDanger, "Device silent: force switched off"};
    case EventKind::kNumerical:
      return {AlertLevel::kDanger, "Simulation failed (" + e.detail + ")"};
    case EventKind::kInstrumentExchange:
      return {AlertLevel::kInfo, "Took the " + e.detail + " from the tray"};
    default: break;
  }
  return {};
}

bool is_zone_event(EventKind kind) {
  return kind == EventKind::kNeverEvent || kind == EventKind::kZoneEntry ||
         kind == EventKind::kZoneForce || kind == EventKind::kZoneWarning;
}

}  // namespace

HudModel make_hud_model(const ScenarioModel& scenario, const WorldSummary& summary,
                        const LiveView& view, const HapticLoopStats& haptics,
                        const std::string& input_label, double recent_s) {
  HudModel hud;
  const Frame& f = view.state.frame;
  hud.title = scenario.title;
  hud.goal = scenario.goal;
  hud.input_label = input_label;
  hud.t_s = f.t_s;
  hud.time_limit_s = scenario.time_limit_s;
  hud.hand_force_N = f.feedback_force_N.norm();
  hud.device_max_N = summary.device_max_force_N;
  hud.tissue_force_N = (f.nucleus_force_N + f.contact_force_N).norm();
  hud.moment_Nm = f.bending_moment_Nm;
  hud.warning_moment_Nm = summary.warning_moment_Nm;
  hud.yield_moment_Nm = summary.yield_moment_Nm;
  hud.removed_target = f.removed_target;
  hud.initial_target = summary.initial_target;
  hud.particle_volume_m3 = summary.particle_volume_m3;
  hud.haptic_rate_hz = haptics.rate_hz;
  hud.target_rate_hz = haptics.target_rate_hz;
  if (haptics.target_rate_hz > 0 && haptics.ticks > 100)
    hud.realtime_factor = haptics.rate_hz / haptics.target_rate_hz;

  // The instrument in hand (tray instruments are named): the first until the hand takes another.
  const std::vector<InstrumentConfig>& tray = scenario.world.instruments;
  if (tray.size() > 1) {
    const int in_hand = instrument_in_hand(view.events, f.t_s);
    if (in_hand >= 0 && in_hand < static_cast<int>(tray.size()))
      hud.instrument = tray[static_cast<std::size_t>(in_hand)].name;
    hud.tray_size = static_cast<int>(tray.size());
  }

  // Live state first: it is what the trainee must react to now.
  if (view.sample.stale)
    hud.alerts.push_back({AlertLevel::kDanger, "Device silent: force switched off, holding"});
  if (summary.yield_moment_Nm > 0 && f.bending_moment_Nm > summary.yield_moment_Nm)
    hud.alerts.push_back({AlertLevel::kDanger, "Shaft over its yield moment: stop levering"});
  else if (summary.warning_moment_Nm > 0 && f.bending_moment_Nm > summary.warning_moment_Nm)
    hud.alerts.push_back(
        {AlertLevel::kWarning,
         "Shaft overload: " +
             format("%.0f %% of yield", 100.0 * f.bending_moment_Nm / summary.yield_moment_Nm) +
             ", ease off"});
  if (!f.input_valid && !view.sample.stale)
    hud.alerts.push_back({AlertLevel::kWarning, "Device pose rejected: holding the instrument"});

  // One line per zone, with its latest state: inside, close, or what happened in the last
  // `recent_s` (entered, force over its limit); a never-event stays said to the end.
  const int zones = std::min<int>(f.zone_count, static_cast<int>(f.zones.size()));
  for (int z = 0; z < zones; ++z) {
    const std::string name = static_cast<std::size_t>(z) < summary.zones.size()
                                 ? zone_display_name(summary.zones[static_cast<std::size_t>(z)].name)
                                 : "zone " + std::to_string(z + 1);
    const char* zone_word = name.find("zone") == std::string::npos ? " zone" : "";
    bool never = false, entered = false;
    double over_force = 0.0;
    for (const Event& e : view.events) {
      if (e.zone != z) continue;
      never = never || e.kind == EventKind::kNeverEvent;
      const bool recent = e.t_s >= f.t_s - recent_s;
      entered = entered || (recent && e.kind == EventKind::kZoneEntry);
      if (recent && e.kind == EventKind::kZoneForce) over_force = std::max(over_force, e.value);
    }
    std::string text;
    AlertLevel level = AlertLevel::kWarning;
    if (f.zones[z].inside) {
      text = "Inside the " + name + zone_word + ": withdraw.";
      level = AlertLevel::kDanger;
    } else if (f.zones[z].warning) {
      text = "Close to the " + name + zone_word + ": " +
             format("%.1f mm away.", 1e3 * f.zones[z].distance_m);
    } else if (entered) {
      text = "Entered the " + name + zone_word + " just now.";
      level = AlertLevel::kDanger;
    }
    if (over_force > 0) {
      text += (text.empty() ? "Force near the " + name + zone_word : std::string(" Force")) +
              " over its limit (" + format("%.2f N", over_force) + ").";
      level = std::max(level, AlertLevel::kWarning);
    }
    if (never) {
      text = (text.empty() ? "Entered the " + name + zone_word + "." : text) +
             " A never-event: the attempt fails.";
      level = AlertLevel::kDanger;
    }
    if (!text.empty()) hud.alerts.push_back({level, text});
  }
  // Then other recent events, newest first, one line for each kind.
  std::vector<EventKind> said;
  for (auto it = view.events.rbegin(); it != view.events.rend(); ++it) {
    if (it->t_s < f.t_s - recent_s) break;
    if (is_zone_event(it->kind)) continue;
    if (std::find(said.begin(), said.end(), it->kind) != said.end()) continue;
    HudAlert a = alert_for_event(*it);
    if (a.text.empty()) continue;
    said.push_back(it->kind);
    const bool seen = std::any_of(hud.alerts.begin(), hud.alerts.end(),
                                  [&](const HudAlert& b) { return b.text == a.text; });
    if (!seen) hud.alerts.push_back(std::move(a));
  }
  std::stable_sort(hud.alerts.begin(), hud.alerts.end(), [](const HudAlert& a, const HudAlert& b) {
    return static_cast<int>(a.level) > static_cast<int>(b.level);
  });
  if (hud.alerts.size() > kMaxHudAlerts) hud.alerts.resize(kMaxHudAlerts);
  return hud;
}

bool is_slow_motion(double factor) { return factor > 0 && factor < 0.95; }

std::string realtime_text(double factor) {
  if (factor <= 0) return "";
  if (is_slow_motion(factor))
    return format("%.2fx real time: slow motion. ", factor) +
           "Use a coarser lattice (a larger particle spacing) or a faster machine.";
  return format("Real time (%.2fx)", std::min(factor, 1.0));
}

void draw_gauge(const char* label, double value, double full, double warn, double danger,
                const char* value_text, float width) {
  ImGui::TextUnformatted(label);
  const float w = width > 0 ? width : ImGui::GetContentRegionAvail().x;
  const float h = ImGui::GetFrameHeight();
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  const ImVec2 p1(p0.x + w, p0.y + h);
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddRectFilled(p0, p1, color_u32(ImVec4(0.16f, 0.17f, 0.20f, 1.0f)), 3.0f);
  const double fraction = full > 0 ? std::clamp(value / full, 0.0, 1.0) : 0.0;
  const ImVec4& fill = danger > 0 && value >= danger ? ui_colors::kDanger
                       : warn > 0 && value >= warn   ? ui_colors::kWarning
                                                     : ui_colors::kOk;
  dl->AddRectFilled(p0, ImVec2(p0.x + static_cast<float>(fraction) * w, p1.y), color_u32(fill),
                    3.0f);
  // Limit marks: a tick where each limit lies on the scale.
  auto mark = [&](double at, const ImVec4& c) {
    if (at <= 0 || full <= 0 || at > full) return;
    const float x = p0.x + static_cast<float>(at / full) * w;
    dl->AddLine(ImVec2(x, p0.y - 2), ImVec2(x, p1.y + 2), color_u32(c), 2.0f);
  };
  mark(warn, ui_colors::kWarning);
  mark(danger, ui_colors::kDanger);
  const ImVec2 text_size = ImGui::CalcTextSize(value_text);
  dl->AddText(ImVec2(p0.x + (w - text_size.x) * 0.5f, p0.y + (h - text_size.y) * 0.5f),
              IM_COL32(255, 255, 255, 255), value_text);
  ImGui::Dummy(ImVec2(w, h));
}

void draw_trainee_hud(const HudModel& hud, const ImVec2& display, HudActions* actions) {
  const ImGuiWindowFlags fixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                 ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings;
  const float margin = 10.0f;

  // Module: title and goal, top left.
  const float goal_width = std::min(460.0f, display.x * 0.42f);
  ImGui::SetNextWindowPos(ImVec2(margin, margin));
  ImGui::SetNextWindowSize(ImVec2(goal_width, 0));
  ImGui::Begin("Module", nullptr, fixed | ImGuiWindowFlags_AlwaysAutoResize);
  ImGui::PushTextWrapPos(goal_width - 12.0f);
  // A long title wraps like the goal under it instead of running out of the panel.
  text_colored_wrapped(ui_colors::kInfo, "%s", hud.title.c_str());
  text_wrapped("%s", hud.goal.c_str());
  ImGui::PopTextWrapPos();
  ImGui::TextColored(ui_colors::kMuted, "Input: %s", hud.input_label.c_str());
  ImGui::End();

  // Status: time, removal, force and shaft load, top right.
  const float status_width = std::min(330.0f, display.x * 0.3f);
  ImGui::SetNextWindowPos(ImVec2(display.x - status_width - margin, margin));
  ImGui::SetNextWindowSize(ImVec2(status_width, 0));
  ImGui::Begin("Status", nullptr, fixed | ImGuiWindowFlags_AlwaysAutoResize);
  if (!hud.instrument.empty()) {
    ImGui::TextColored(ui_colors::kInfo, "In hand: %s", hud.instrument.c_str());
    ImGui::SameLine();
    ImGui::TextColored(ui_colors::kMuted, "(tray of %d)", hud.tray_size);
  }
  char text[128];
  if (hud.time_limit_s > 0) {
    const double left = std::max(0.0, hud.time_limit_s - hud.t_s);
    std::snprintf(text, sizeof text, "%.1f s elapsed, %.1f s left", hud.t_s, left);
    draw_gauge("Time", hud.t_s, hud.time_limit_s, 0.8 * hud.time_limit_s, 0.95 * hud.time_limit_s,
               text);
  } else {
    ImGui::Text("Time: %.1f s elapsed", hud.t_s);
  }
  const double removed =
      hud.initial_target > 0 ? static_cast<double>(hud.removed_target) / hud.initial_target : 0.0;
  std::snprintf(text, sizeof text, "%.1f %%  (%.0f mm³)", 100.0 * removed,
                hud.removed_target * hud.particle_volume_m3 * 1e9);
  ImGui::TextUnformatted("Nucleus removed");
  ImGui::PushStyleColor(ImGuiCol_PlotHistogram, ui_colors::kOk);
  ImGui::ProgressBar(static_cast<float>(removed), ImVec2(-1, 0), text);
  ImGui::PopStyleColor();
  // The force on the hand against the device's rated maximum (amber from 80 %).
  std::snprintf(text, sizeof text, "%.2f N of %.1f N", hud.hand_force_N, hud.device_max_N);
  draw_gauge("Force on the hand", hud.hand_force_N, hud.device_max_N * 1.05,
             0.8 * hud.device_max_N, hud.device_max_N * 0.999, text);
  // The shaft's bending moment against the overload warning and the yield moment.
  std::snprintf(text, sizeof text, "%.0f %% of yield",
                hud.yield_moment_Nm > 0 ? 100.0 * hud.moment_Nm / hud.yield_moment_Nm : 0.0);
  draw_gauge("Shaft load (overload)", hud.moment_Nm, hud.yield_moment_Nm * 1.2,
             hud.warning_moment_Nm, hud.yield_moment_Nm, text);
  ImGui::TextColored(ui_colors::kMuted, "Tissue force %.2f N", hud.tissue_force_N);
  // The real-time factor: a slow-motion attempt is said plainly, with what to do.
  if (is_slow_motion(hud.realtime_factor)) {
    ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + ImGui::GetContentRegionAvail().x);
    ImGui::PushStyleColor(ImGuiCol_Text, ui_colors::kWarning);
    text_wrapped("%s", realtime_text(hud.realtime_factor).c_str());
    ImGui::PopStyleColor();
    ImGui::PopTextWrapPos();
  } else if (hud.realtime_factor > 0) {
    ImGui::TextColored(ui_colors::kMuted, "%s, haptic loop %.0f Hz",
                       realtime_text(hud.realtime_factor).c_str(), hud.haptic_rate_hz);
  }
  if (actions) actions->status_bottom = ImGui::GetWindowPos().y + ImGui::GetWindowSize().y;
  ImGui::End();

  // Alerts: most severe first, in the column between the module and the status windows (they
  // never cover the goal or the gauges); a long line wraps.
  if (!hud.alerts.empty()) {
    const float left = margin + goal_width + margin;
    const float width = std::max(200.0f, display.x - status_width - margin - left - margin);
    ImGui::SetNextWindowPos(ImVec2(left, margin));
    ImGui::SetNextWindowSize(ImVec2(width, 0));
    ImGui::SetNextWindowBgAlpha(0.85f);
    ImGui::Begin("Alerts", nullptr,
                 fixed | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoTitleBar);
    ImGui::PushTextWrapPos(width - ImGui::GetStyle().WindowPadding.x);
    for (const HudAlert& a : hud.alerts) {
      ImGui::PushStyleColor(ImGuiCol_Text, level_color(a.level));
      text_wrapped("%s %s", a.level == AlertLevel::kDanger ? "[!]" : "[~]", a.text.c_str());
      ImGui::PopStyleColor();
    }
    ImGui::PopTextWrapPos();
    ImGui::End();
  }

  // Controls: bottom left.
  ImGui::SetNextWindowPos(ImVec2(margin, display.y - margin), ImGuiCond_Always, ImVec2(0, 1));
  ImGui::Begin("Controls", nullptr, fixed | ImGuiWindowFlags_AlwaysAutoResize);
  if (hud.mouse_mode) {
    // The instrument's controls first: they are what a trainee needs to learn.
    ImGui::TextColored(ui_colors::kInfo, "Instrument (mouse)");
    ImGui::TextUnformatted("Left-drag: move across  |  Wheel or right-drag: depth");
    ImGui::TextUnformatted("Ctrl + left-drag: tilt / roll the cup  |  Space: hold still  |  F: close the jaws");
    if (hud.tray_size > 1)
      ImGui::TextUnformatted("T: take the next instrument from the tray (out of the disc)");
    ImGui::TextColored(ui_colors::kMuted,
                       "Camera: middle-drag orbit, Shift + middle-drag pan, Ctrl + wheel zoom");
  } else {
    ImGui::TextColored(ui_colors::kMuted, "Camera: right-drag orbit, wheel zoom, middle-drag pan");
  }
  const bool finish = ImGui::Button("Finish attempt (Enter)");
  ImGui::SameLine();
  const bool reset = ImGui::Button("Reset camera (R)");
  bool stress = false;
  if (hud.stress_view_available) {
    ImGui::SameLine();
    bool on = hud.stress_view_on;
    stress = ImGui::Checkbox("Bone stress (B)", &on);
  }
  ImGui::End();
  if (actions) {
    actions->toggle_stress_view = actions->toggle_stress_view || stress;
    actions->finish = actions->finish || finish;
    actions->reset_camera = actions->reset_camera || reset;
  }
}

ScoreScreenModel make_score_screen(const ScenarioModel& scenario, const AttemptRun& run,
                                   const std::string& status_line) {
  ScoreScreenModel s;
  s.title = scenario.title;
  s.score = run.score.score;
  s.pass_score = scenario.rubric.pass_score;
  s.passed = run.score.passed;
  s.end_reason = attempt_end_name(run.end);
  s.duration_s = run.record.frames.empty() ? 0.0 : run.record.frames.back().t_s;
  s.realtime_factor = run.wall_s > 0 ? s.duration_s / run.wall_s : 0.0;
  s.status_line = status_line;
  s.consecutive_passes_to_master = scenario.rubric.consecutive_passes_to_master;
  s.rows = score_table(run.metrics, run.score, &scenario.rubric, ScoreTableScope::kAssessed);
  s.scale = score_scale_text(&scenario.rubric);
  // What happened in the danger zones, by the zones' names.
  std::vector<std::string> zone_names;
  for (const auto& z : run.record.summary.zones) zone_names.push_back(z.name);
  for (const ZoneFinding& f : zone_findings(run.metrics, zone_names)) {
    std::string text = f.text;
    if (!text.empty()) text[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(text[0])));
    s.zone_findings.push_back(text + ".");
  }
  // What to improve: each weak metric against the experts, each failed gate, then the reasons.
  for (const ScoreTableRow& row : s.rows) {
    if (row.good) continue;
    if (row.withheld) continue;  // said once by the reason below
    if (!row.measured) continue;  // the reason below says it was not measured
    if (row.judgement == MetricJudgement::kScored && row.benchmark)
      s.improvements.push_back(row.label + ": yours " + format("%.3g", row.value) +
                               ", experts " + format("%.3g", row.benchmark->expert_mean) +
                               (row.benchmark->higher_is_better ? " - aim higher."
                                                                : " - aim lower."));
    else if (row.judgement == MetricJudgement::kGated)
      s.improvements.push_back(row.label + ": " + format("%.3g", row.value) +
                               ", must stay at or below " + format("%.3g", row.gate_max) + ".");
  }
  for (const std::string& r : run.score.reasons) {
    // A failed gate is said above in words, a never-event by the zone findings.
    bool said = std::find(s.improvements.begin(), s.improvements.end(), r) != s.improvements.end();
    for (const ScoreTableRow& row : s.rows)
      said = said || (row.judgement == MetricJudgement::kGated && !row.good &&
                      r.rfind(row.metric + " = ", 0) == 0);
    said = said || (!s.zone_findings.empty() && r.rfind("never-event:", 0) == 0);
    if (!said && !r.empty()) {
      std::string line = r;  // a sentence on the screen
      line[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(line[0])));
      s.improvements.push_back(line + (line.back() == '.' ? "" : "."));
    }
  }
  if (s.improvements.empty())
    s.improvements.push_back(
        "Every metric is at expert level or better. Pass " +
        std::to_string(s.consecutive_passes_to_master) +
        " attempts in a row to master the module.");
  return s;
}

bool draw_score_screen(const ScoreScreenModel& s, const ImVec2& display) {
  const float width = std::min(960.0f, display.x - 40.0f);
  ImGui::SetNextWindowPos(ImVec2(display.x * 0.5f, display.y * 0.5f), ImGuiCond_Always,
                          ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowSize(ImVec2(width, 0));
  ImGui::Begin("Score", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                   ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings);
  // Every line wraps inside the window (window-local x), the long end reason and status too.
  ImGui::PushTextWrapPos(ImGui::GetContentRegionMax().x);  // inside a scrollbar too
  ImGui::TextColored(ui_colors::kInfo, "%s", s.title.c_str());
  text_wrapped("Ended: %s after %.1f s", s.end_reason.c_str(), s.duration_s);
  if (is_slow_motion(s.realtime_factor)) {
    ImGui::PushTextWrapPos(ImGui::GetContentRegionMax().x);  // inside a scrollbar too
    ImGui::PushStyleColor(ImGuiCol_Text, ui_colors::kWarning);
    text_wrapped("The simulation ran at %s", realtime_text(s.realtime_factor).c_str());
    ImGui::PopStyleColor();
    ImGui::PopTextWrapPos();
  }
  ImGui::Separator();
  ImGui::SetWindowFontScale(2.0f);
  ImGui::Text("Score %.1f / 100", s.score);
  ImGui::SameLine();
  ImGui::TextColored(s.passed ? ui_colors::kOk : ui_colors::kDanger, "  %s",
                     s.passed ? "PASSED" : "NOT PASSED");
  ImGui::SetWindowFontScale(1.0f);
  ImGui::TextColored(ui_colors::kMuted, "Pass at %.0f, with every safety gate held.",
                     s.pass_score);
  ImGui::Spacing();
  draw_score_table("metrics", s.rows);
  // Long lines wrap inside the window (window-local x).
  ImGui::PushTextWrapPos(ImGui::GetContentRegionMax().x);  // inside a scrollbar too
  auto bullet = [](const std::string& line) {
    ImGui::Bullet();
    text_wrapped("%s", line.c_str());
  };
  if (!s.zone_findings.empty()) {
    ImGui::Spacing();
    ImGui::TextColored(ui_colors::kDanger, "In the danger zones");
    for (const std::string& line : s.zone_findings) bullet(line);
  }
  ImGui::Spacing();
  ImGui::TextUnformatted("What to improve");
  for (const std::string& line : s.improvements) bullet(line);
  ImGui::Spacing();
  ImGui::TextColored(ui_colors::kMuted, "How to read the scores");
  for (const std::string& line : s.scale) text_colored_wrapped(ui_colors::kMuted, "%s", line.c_str());
  ImGui::PopTextWrapPos();
  if (!s.status_line.empty()) {
    ImGui::Spacing();
    ImGui::TextColored(ui_colors::kMuted, "%s", s.status_line.c_str());
  }
  ImGui::Spacing();
  const bool close = ImGui::Button("Close (Enter)");
  ImGui::PopTextWrapPos();
  ImGui::End();
  return close;
}

}  // namespace acdr
