// The instructor dashboard's data, read from the training record (db/) into plain structs the
// view draws: trainees with their curriculum progress and attempts, and, for one selected
// attempt, its decoded recording turned into time series (forces, shaft moment, removal,
// tip path) and bands (overload, rejected or lost input), with what it needs of its module's
// scenario (benchmarks, the replay's geometry). Also the CSV of whatever the dashboard
// currently shows. No ImGui here, so all of it can be tested without a screen.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/score_table.hpp"
#include "assessment/attempt_recording.hpp"
#include "assessment/rubric.hpp"
#include "db/database.hpp"
#include "db/progression.hpp"
#include "db/records.hpp"
#include "engine/core/types.hpp"
#include "engine/geometry/collider.hpp"
#include "ui/mesh_silhouette.hpp"

namespace acdr {

class BoneStressPane;  // ui/bone_stress_pane.hpp

struct DashboardTrainee {
  TraineeRecord info;
  std::vector<ModuleProgress> progress;  ///< one per module, in curriculum order
  std::vector<AttemptRecord> attempts;   ///< in start order, with metrics and score detail
};

struct DashboardModel {
  std::string db_path;
  std::vector<ModuleRecord> modules;         ///< curriculum order
  std::vector<DashboardTrainee> trainees;    ///< by id
  std::vector<AttemptRecord> practice;       ///< attempts without a trainee

  const DashboardTrainee* find_trainee(const std::string& id) const;
  const ModuleRecord* find_module(const std::string& id) const;
};

/// Reads everything but recordings in one consistent snapshot (a read transaction). Reads no
/// scenario file: what an attempt needs of its module's scenario comes with its drill-down.
DbResult<DashboardModel> load_dashboard(Database& db);

/// One shaded interval of time.
struct TimeBand {
  double t0_s = 0.0, t1_s = 0.0;
};

/// What the replay draws besides the recorded frames: the box walls and the instrument's shape
/// from the module's scenario, and the bounds of the walls and the whole tip path. Built once,
/// when the attempt is opened, so drawing needs neither the scenario file nor the engine.
struct ReplayGeometry {
  std::vector<Collider> walls;       ///< the box's walls, world frame
  /// Each instrument on the scene's tray (one for a single instrument): its colliders in its
  /// grip frame; empty: no instrument.
  std::vector<std::vector<Collider>> tray;
  /// The recording's instrument exchanges, in time order (instrument_in_hand reads them).
  std::vector<Event> exchanges;
  /// The vertebrae's outlines in the two replay views (x-y from above, x-z along the spine);
  /// empty in scenes without anatomy.
  MeshSilhouette bone_top, bone_side;
  std::string bone_note;  ///< why the vertebrae are not shown, when the scene has them but they could not be loaded
  Eigen::AlignedBox3d bounds;        ///< the walls and every recorded tip position (m)

  /// The colliders of the instrument in hand at t_s with its grip at `grip` (world frame), into
  /// `out` (empty without an instrument).
  void instrument_at(const Pose& grip, double t_s, std::vector<Collider>& out) const;
};

/// An attempt opened for drill-down: its record with events and the decoded recording as
/// series (one entry per frame, floats for plotting).
struct AttemptDrillDown {
  AttemptRecord record;
  std::optional<AttemptRecording> recording;  ///< nullopt: none stored, or it failed to decode
  std::string recording_error;
  std::vector<float> t_s;
  std::vector<float> hand_force_N;     ///< |force sent to the device|
  std::vector<float> tissue_force_N;   ///< |nucleus reaction + rigid contact| on the instrument
  std::vector<float> moment_Nm;        ///< shaft bending moment
  std::vector<float> removed_fraction; ///< nucleus removed so far / initial nucleus
  std::vector<TimeBand> overload_warning;  ///< moment above the warning fraction of yield
  std::vector<TimeBand> overload_yield;    ///< moment above yield
  std::vector<TimeBand> input_invalid;     ///< device input rejected or lost
  std::vector<TimeBand> zone_warning;      ///< within a danger zone's warning distance
  std::vector<TimeBand> zone_inside;       ///< inside a danger zone
  double duration_s = 0.0;
  /// From the module's scenario file, read once here: its rubric (the benchmarks) and the
  /// replay's walls and instrument. nullopt / empty with `scenario_error` set when the file
  /// cannot be loaded.
  std::optional<Rubric> rubric;
  ReplayGeometry replay;
  std::string scenario_error;
  /// Every recorded metric against its benchmark, as the attempt was scored.
  std::vector<ScoreTableRow> metric_rows;
  /// What happened near the danger zones, in words (zone names from the recording when it
  /// decodes, else the zone ids of the metrics).
  std::vector<std::string> zone_findings;
  /// How to read the scores (score_scale_text of the module's rubric).
  std::vector<std::string> scale;
  /// The bone's stress at the replay's time (ui/bone_stress_pane.hpp): null when the module
  /// does not model the bone or the recording has no bone loads; `bone_stress_note` says why
  /// when the module models it.
  std::shared_ptr<BoneStressPane> bone_stress;
  std::string bone_stress_note;

  /// Index of the last frame at or before time t (0 when none).
  std::size_t frame_at(double t_s) const;
  /// Where the replay cursor opens: the moment of peak bone load when the bone was modelled
  /// (so the stress pane shows the worst of the attempt), else 0.6 of the way through.
  double opening_t_s() const;
};

/// Loads attempt `id` with events and recording, and its module's scenario file for the
/// benchmarks and the replay's geometry. Null with `error` when there is no such attempt or the
/// store fails; a recording that does not decode is reported in recording_error, a scenario
/// that does not load in scenario_error, with the rest still shown.
std::unique_ptr<AttemptDrillDown> load_drill_down(Database& db, std::int64_t id,
                                                  std::string* error);

/// The cell state of the progress matrix: "locked", "not started", "in progress", "passed"
/// (passed at least once, not yet mastered) or "mastered".
std::string progress_state(const ModuleProgress& progress);

/// What the dashboard shows: which trainee, module and attempt are selected.
struct DashboardSelection {
  std::string trainee_id;     ///< empty: none
  std::string module_id;      ///< the learning curve's module
  std::int64_t attempt_id = 0;  ///< 0: none
  double replay_t_s = 0.0;
};

/// A first selection for a fresh dashboard: the first trainee with attempts, the module of
/// their latest attempt, and that attempt.
DashboardSelection default_selection(const DashboardModel& model);

/// The attempts of `trainee` at `module`, completed or aborted, in start order (the learning
/// curve's points).
std::vector<const AttemptRecord*> curve_attempts(const DashboardTrainee& trainee,
                                                 const std::string& module_id);

/// The CSV of the current view: the attempt's frames when an attempt is open, else the
/// selected trainee's attempts, else the progress matrix. Header line first; one record per
/// line; text fields quoted when they hold a comma or quote.
std::string dashboard_csv(const DashboardModel& model, const DashboardSelection& selection,
                          const AttemptDrillDown* attempt);

/// A file name for that CSV: dashboard-progress.csv, dashboard-<trainee>.csv or
/// dashboard-attempt-<id>.csv.
std::string dashboard_csv_name(const DashboardSelection& selection,
                               const AttemptDrillDown* attempt);

}  // namespace acdr
