// The trainee view's Dear ImGui overlay, as plain functions of plain models so the same code
// draws into the window and into offscreen test pictures:
//  - the HUD while the attempt runs: module title and goal, elapsed and remaining time, a force
//    gauge against the device's rated maximum, the shaft load against its overload warning and
//    yield, nucleus removed as a progress bar, alerts (zone, overload, device), controls;
//  - the score screen at the end: composite score, pass/fail, each metric against its
//    benchmark, safety gates, and what to improve.
#pragma once

#include <string>
#include <vector>

#include <imgui.h>

#include "app/attempt_runner.hpp"
#include "app/live_attempt.hpp"
#include "app/score_table.hpp"
#include "engine/devices/haptic_loop.hpp"
#include "scenarios/scenario_model.hpp"

namespace acdr {

enum class AlertLevel { kInfo, kWarning, kDanger };

struct HudAlert {
  AlertLevel level = AlertLevel::kInfo;
  std::string text;
};

/// Everything the HUD shows, in SI units.
struct HudModel {
  std::string title;
  std::string goal;
  std::string input_label;        ///< "mouse", "udp:7000", "replay:..."
  double t_s = 0.0;
  double time_limit_s = 0.0;      ///< 0: none
  double hand_force_N = 0.0;      ///< force rendered to the device (after safety limits)
  double device_max_N = 0.0;      ///< the device's rated maximum
  double tissue_force_N = 0.0;    ///< instrument force on material and walls
  double moment_Nm = 0.0;         ///< shaft bending moment
  double warning_moment_Nm = 0.0;
  double yield_moment_Nm = 0.0;
  int removed_target = 0;         ///< particles of nucleus removed
  int initial_target = 0;
  double particle_volume_m3 = 0.0;
  double haptic_rate_hz = 0.0;    ///< achieved haptic loop rate
  double target_rate_hz = 0.0;
  /// Simulated seconds per wall second so far (haptic rate / target rate); 0: not known yet.
  double realtime_factor = 0.0;
  /// The instrument in hand, when the scene's tray holds more than one ("" otherwise), and
  /// how many the tray holds.
  std::string instrument;
  int tray_size = 0;
  bool mouse_mode = false;        ///< the mouse drives the instrument (show the mapping)
  bool stress_view_available = false;  ///< the scene models the bone: offer its stress view
  bool stress_view_on = false;
  std::vector<HudAlert> alerts;   ///< most severe first
};

/// The HUD model of a live view: live state (moment, force, stale input) and events of the
/// last `recent_s` seconds (zones, overload, clamping, rejected input, an instrument taken from
/// the tray) become alerts; the exchanges also say which instrument is in hand.
HudModel make_hud_model(const ScenarioModel& scenario, const WorldSummary& summary,
                        const LiveView& view, const HapticLoopStats& haptics,
                        const std::string& input_label, double recent_s = 2.0);

/// What the trainee asked for through the HUD this frame.
struct HudActions {
  bool finish = false;        ///< "Finish attempt" pressed: score what was done
  bool reset_camera = false;
  bool toggle_stress_view = false;  ///< "Bone stress" clicked
  float status_bottom = 0.0f;       ///< where the status window ends (pixels from the top), for panes below it
};

/// "0.37x real time: slow motion. Use a coarser lattice or a faster machine." below 0.95;
/// "real time (1.00x)" at or above it; "" when `factor` <= 0 (not known).
std::string realtime_text(double factor);
/// Whether `factor` is slow motion (known and below 0.95).
bool is_slow_motion(double factor);

/// Draws the HUD for a display of `display` pixels. `actions` may be null.
void draw_trainee_hud(const HudModel& hud, const ImVec2& display, HudActions* actions);

struct ScoreScreenModel {
  std::string title;
  double score = 0.0;
  double pass_score = 50.0;
  bool passed = false;
  std::string end_reason;   ///< "time limit", "input ended", ...
  double duration_s = 0.0;
  double realtime_factor = 0.0;  ///< simulated / wall time of the attempt; 0: not known
  std::vector<ScoreTableRow> rows;  ///< the scored metrics, then the safety gates
  std::vector<std::string> zone_findings;  ///< what happened near the danger zones, in words
  std::vector<std::string> improvements;  ///< what to improve, in words
  std::vector<std::string> scale;         ///< how to read the scores (score_scale_text)
  std::string status_line;  ///< e.g. "Stored as attempt 12"
  int consecutive_passes_to_master = 2;
};

ScoreScreenModel make_score_screen(const ScenarioModel& scenario, const AttemptRun& run,
                                   const std::string& status_line);

/// Draws the score screen centred on the display; returns true when "Close" was pressed.
bool draw_score_screen(const ScoreScreenModel& score, const ImVec2& display);

/// A horizontal gauge: `value` on a 0..`full` scale with coloured limit marks; the bar turns
/// amber past `warn` and red past `danger` (either may be <= 0 to disable).
void draw_gauge(const char* label, double value, double full, double warn, double danger,
                const char* value_text, float width = -1.0f);

}  // namespace acdr
