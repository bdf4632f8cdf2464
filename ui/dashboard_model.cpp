// Dashboard data from the record.
#include "ui/dashboard_model.hpp"

#include <algorithm>
#include <cstdio>

#include "assessment/recording.hpp"
#include "assessment/zone_findings.hpp"
#include "db/attempt_store.hpp"
#include "db/catalog.hpp"
#include "engine/anatomy/anatomy.hpp"
#include "engine/rigid/instrument.hpp"
#include "engine/rigid/static_scene.hpp"
#include "scenarios/scenario_loader.hpp"
#include "ui/bone_stress_pane.hpp"

namespace acdr {

const DashboardTrainee* DashboardModel::find_trainee(const std::string& id) const {
  for (const DashboardTrainee& t : trainees)
    if (t.info.id == id) return &t;
  return nullptr;
}

const ModuleRecord* DashboardModel::find_module(const std::string& id) const {
  for (const ModuleRecord& m : modules)
    if (m.id == id) return &m;
  return nullptr;
}

DbResult<DashboardModel> load_dashboard(Database& db) {
  DashboardModel model;
  model.db_path = db.path();
  {
    // One snapshot: an attempt finishing meanwhile shows everywhere or nowhere.
    DbResult<Transaction> tx = Transaction::begin(db, Transaction::Mode::kDeferred);
    if (!tx) return tx.error();
    auto modules = list_modules(db);
    if (!modules) return modules.error();
    model.modules = std::move(modules.value());
    auto trainees = list_trainees(db);
    if (!trainees) return trainees.error();
    for (TraineeRecord& info : trainees.value()) {
      DashboardTrainee t;
      t.info = std::move(info);
      auto progress = trainee_progress(db, t.info.id);
      if (!progress) return progress.error();
      t.progress = std::move(progress.value());
      AttemptFilter filter;
      filter.trainee_id = t.info.id;
      filter.include_practice = false;
      auto attempts = list_attempts(db, filter);
      if (!attempts) return attempts.error();
      t.attempts = std::move(attempts.value());
      model.trainees.push_back(std::move(t));
    }
    auto all = list_attempts(db);
    if (!all) return all.error();
    for (AttemptRecord& a : all.value())
      if (a.is_practice()) model.practice.push_back(std::move(a));
    (void)tx->commit();
  }
  return model;
}

std::size_t AttemptDrillDown::frame_at(double t) const {
  if (t_s.empty()) return 0;
  const auto it = std::upper_bound(t_s.begin(), t_s.end(), static_cast<float>(t));
  return it == t_s.begin() ? 0 : static_cast<std::size_t>(it - t_s.begin()) - 1;
}

double AttemptDrillDown::opening_t_s() const {
  if (bone_stress && bone_stress->peak_load_N() > 0.0) return bone_stress->peak_load_t_s();
  return 0.6 * duration_s;
}

void ReplayGeometry::instrument_at(const Pose& grip, double t_s, std::vector<Collider>& out) const {
  out.clear();
  const int k = instrument_in_hand(exchanges, t_s);
  if (k < 0 || k >= static_cast<int>(tray.size())) return;
  const std::vector<Collider>& local = tray[static_cast<std::size_t>(k)];
  out.resize(local.size());
  for (std::size_t i = 0; i < local.size(); ++i) {
    out[i] = local[i];
    out[i].pose.position = grip.apply(local[i].pose.position);
    out[i].pose.orientation = grip.orientation * local[i].pose.orientation;
  }
}

namespace {

// The corners of a box collider (world frame) into `bounds`.
void extend_by_box(const Collider& c, Eigen::AlignedBox3d& bounds) {
  for (int k = 0; k < 8; ++k)
    bounds.extend(c.pose.apply(Vec3((k & 1 ? 1 : -1) * c.half_extents_m.x(),
                                    (k & 2 ? 1 : -1) * c.half_extents_m.y(),
                                    (k & 4 ? 1 : -1) * c.half_extents_m.z())));
}

// The module's scenario (path as the runs stored it): its rubric and the replay's walls and
// instrument. Sets `d.scenario_error` when it cannot be read.
// Returns the scenario (null when it cannot be read).
std::shared_ptr<const ScenarioModel> load_scenario_parts(Database& db, AttemptDrillDown& d) {
  auto module = find_module(db, d.record.module_id);
  if (!module || !module.value() || module.value()->scenario_path.empty()) {
    d.scenario_error = !module ? module.error().message : "no scenario file recorded";
    return nullptr;
  }
  const std::string& path = module.value()->scenario_path;
  const LoadResult loaded = load_scenario_file(path);
  if (!loaded.ok()) {
    d.scenario_error =
        path + ": " + (loaded.errors.empty() ? "cannot load" : to_string(loaded.errors));
    return nullptr;
  }
  const WorldConfig& world = loaded.model->world;
  d.rubric = loaded.model->rubric;
  for (const Collider& c : build_static_colliders(world.ground, world.box)) {
    if (c.kind != ColliderKind::kBox) continue;
    d.replay.walls.push_back(c);
    extend_by_box(c, d.replay.bounds);
  }
  if (world.instrument.enabled) {
    if (world.instruments.empty())
      d.replay.tray.push_back(InstrumentGeometry(world.instrument).local_colliders());
    for (const InstrumentConfig& ic : world.instruments)
      d.replay.tray.push_back(InstrumentGeometry(ic).local_colliders());
  }
  if (world.anatomy.enabled) {
    // The vertebrae as the attempt had them (from the mesh cache, or the files); a replay
    // without them still shows the instrument and its path.
    try {
      const std::array<TriangleMesh, 2> bone = load_vertebra_meshes(world.anatomy);
      const std::vector<const TriangleMesh*> both = {&bone[0], &bone[1]};
      constexpr double kCell = 0.4e-3;
      d.replay.bone_top = project_silhouette(both, 0, 1, kCell);
      d.replay.bone_side = project_silhouette(both, 0, 2, kCell);
    } catch (const std::exception& e) {
      d.replay.bone_note = std::string("vertebrae not shown: ") + e.what();
    }
  }
  return loaded.model;
}

// Appends to `bands` the intervals where `inside(frame)` holds.
template <class Pred>
void collect_bands(const std::vector<Frame>& frames, Pred inside, std::vector<TimeBand>& bands) {
  bool open = false;
  double start = 0.0;
  for (const Frame& f : frames) {
    const bool in = inside(f);
    if (in && !open) start = f.t_s;
    if (!in && open) bands.push_back({start, f.t_s});
    open = in;
  }
  if (open && !frames.empty()) bands.push_back({start, frames.back().t_s});
}

}  // namespace

std::unique_ptr<AttemptDrillDown> load_drill_down(Database& db, std::int64_t id,
                                                  std::string* error) {
  auto loaded = load_attempt(db, id, AttemptDetail{true, true, true});
  if (!loaded) {
    *error = loaded.error().message;
    return nullptr;
  }
  if (!loaded.value()) {
    *error = "no attempt " + std::to_string(id) + " in " + db.path();
    return nullptr;
  }
  auto d = std::make_unique<AttemptDrillDown>();
  d->record = std::move(*loaded.value());
  const std::shared_ptr<const ScenarioModel> scenario = load_scenario_parts(db, *d);
  d->metric_rows = score_table(d->record.metrics, d->record.score_detail,
                               d->rubric ? &*d->rubric : nullptr, ScoreTableScope::kAllMetrics);
  d->scale = score_scale_text(d->rubric ? &*d->rubric : nullptr);
  auto describe_zones = [&d](const std::vector<std::string>& zone_names) {
    d->zone_findings.clear();
    for (const ZoneFinding& f : zone_findings(d->record.metrics, zone_names))
      d->zone_findings.push_back(f.text);
  };
  describe_zones({});
  if (!d->record.recording) {
    d->recording_error = "no recording stored (the attempt was " +
                         std::string(attempt_status_name(d->record.status)) + ")";
    return d;
  }
  d->recording = decode_recording(d->record.recording->bytes, &d->recording_error);
  d->record.recording.reset();  // the decoded frames are kept instead of the bytes
  if (!d->recording) return d;

  const AttemptRecording& r = *d->recording;
  std::vector<std::string> zone_names;
  for (const auto& z : r.summary.zones) zone_names.push_back(z.name);
  if (!zone_names.empty()) describe_zones(zone_names);
  const std::size_t n = r.frames.size();
  d->t_s.reserve(n);
  d->hand_force_N.reserve(n);
  d->tissue_force_N.reserve(n);
  d->moment_Nm.reserve(n);
  d->removed_fraction.reserve(n);
  const double initial = std::max(1, r.summary.initial_target);
  for (const Frame& f : r.frames) {
    d->t_s.push_back(static_cast<float>(f.t_s));
    d->hand_force_N.push_back(static_cast<float>(f.feedback_force_N.norm()));
    d->tissue_force_N.push_back(static_cast<float>((f.nucleus_force_N + f.contact_force_N).norm()));
    d->moment_Nm.push_back(static_cast<float>(f.bending_moment_Nm));
    d->removed_fraction.push_back(static_cast<float>(f.removed_target / initial));
  }
  const double warn = r.summary.warning_moment_Nm, yield = r.summary.yield_moment_Nm;
  if (warn > 0)
    collect_bands(r.frames, [&](const Frame& f) { return f.bending_moment_Nm > warn; },
                  d->overload_warning);
  if (yield > 0)
    collect_bands(r.frames, [&](const Frame& f) { return f.bending_moment_Nm > yield; },
                  d->overload_yield);
  collect_bands(r.frames, [](const Frame& f) { return !f.input_valid; }, d->input_invalid);
  auto any_zone = [](const Frame& f, bool inside) {
    for (int z = 0; z < f.zone_count && z < static_cast<int>(f.zones.size()); ++z)
      if (inside ? f.zones[z].inside : f.zones[z].warning) return true;
    return false;
  };
  collect_bands(r.frames, [&](const Frame& f) { return any_zone(f, false); }, d->zone_warning);
  collect_bands(r.frames, [&](const Frame& f) { return any_zone(f, true); }, d->zone_inside);
  d->duration_s = n ? r.frames.back().t_s : 0.0;
  for (const Frame& f : r.frames) d->replay.bounds.extend(f.tip_m);
  for (const Event& e : r.events)
    if (e.kind == EventKind::kInstrumentExchange)
      d->replay.exchanges.push_back(e);
  if (scenario && scenario->bone.enabled) {
    // The stresses come from the recorded loads; the scale from the attempt's endplate peak.
    d->bone_stress = BoneStressPane::create(*scenario, r, &d->bone_stress_note);
    if (d->bone_stress)
      if (const double* peak = d->record.metrics.find("endplate_peak_stress_MPa"))
        d->bone_stress->set_scale_top(*peak * 1e6);
  }
  return d;
}

std::string progress_state(const ModuleProgress& p) {
  if (p.mastered) return "mastered";
  if (!p.unlocked) return "locked";
  if (p.run.attempts == 0) return "not started";
  if (p.passed) return "passed";
  return "in progress";
}

DashboardSelection default_selection(const DashboardModel& model) {
  DashboardSelection s;
  for (const DashboardTrainee& t : model.trainees) {
    if (t.attempts.empty()) continue;
    s.trainee_id = t.info.id;
    // The latest completed attempt (one with a recording to show), else the latest.
    const AttemptRecord* pick = &t.attempts.back();
    for (auto it = t.attempts.rbegin(); it != t.attempts.rend(); ++it) {
      if (it->status == AttemptStatus::kCompleted) {
        pick = &*it;
        break;
      }
    }
    s.module_id = pick->module_id;
    s.attempt_id = pick->id;
    return s;
  }
  if (!model.trainees.empty()) s.trainee_id = model.trainees.front().info.id;
  if (!model.modules.empty()) s.module_id = model.modules.front().id;
  return s;
}

std::vector<const AttemptRecord*> curve_attempts(const DashboardTrainee& trainee,
                                                 const std::string& module_id) {
  std::vector<const AttemptRecord*> out;
  for (const AttemptRecord& a : trainee.attempts)
    if (a.module_id == module_id && a.status != AttemptStatus::kRunning) out.push_back(&a);
  return out;
}

namespace {

std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) {
    if (c == '"') q += '"';
    q += c;
  }
  return q + "\"";
}

std::string csv_number(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

template <class T>
std::string csv_optional(const std::optional<T>& v) {
  return v ? csv_number(static_cast<double>(*v)) : "";
}

}  // namespace

std::string dashboard_csv(const DashboardModel& model, const DashboardSelection& selection,
                          const AttemptDrillDown* attempt) {
  std::string csv;
  if (attempt && attempt->recording) {
    // The attempt's frame stream: what the force plot, the removal curve and the replay show.
    csv = "t_s,hand_force_N,tissue_force_N,bending_moment_Nm,removed_fraction,tip_x_mm,"
          "tip_y_mm,tip_z_mm,input_valid\n";
    const auto& frames = attempt->recording->frames;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      const Frame& f = frames[i];
      csv += csv_number(f.t_s) + "," + csv_number(attempt->hand_force_N[i]) + "," +
             csv_number(attempt->tissue_force_N[i]) + "," + csv_number(f.bending_moment_Nm) +
             "," + csv_number(attempt->removed_fraction[i]) + "," +
             csv_number(f.tip_m.x() * 1e3) + "," + csv_number(f.tip_m.y() * 1e3) + "," +
             csv_number(f.tip_m.z() * 1e3) + "," + (f.input_valid ? "1" : "0") + "\n";
    }
    return csv;
  }
  if (const DashboardTrainee* t = model.find_trainee(selection.trainee_id)) {
    // The trainee's attempts with their key metrics (the union of the metric names, in order).
    std::vector<std::string> metrics;
    for (const AttemptRecord& a : t->attempts)
      for (const auto& [name, value] : a.metrics.values)
        if (std::find(metrics.begin(), metrics.end(), name) == metrics.end())
          metrics.push_back(name);
    csv = "attempt_id,trainee_id,module_id,started_utc,status,duration_s,realtime_factor,score,"
          "passed,input_device";
    for (const std::string& m : metrics) csv += "," + csv_text(m);
    csv += "\n";
    for (const AttemptRecord& a : t->attempts) {
      csv += std::to_string(a.id) + "," + csv_text(t->info.id) + "," + csv_text(a.module_id) +
             "," + csv_text(a.started_utc) + "," + attempt_status_name(a.status) + "," +
             csv_optional(a.duration_s) + "," + csv_optional(a.realtime_factor) + "," +
             csv_optional(a.score) + "," +
             (a.passed ? (*a.passed ? "1" : "0") : "") + "," + csv_text(a.input_device);
      for (const std::string& m : metrics) {
        const double* v = a.metrics.find(m);
        csv += "," + (v ? csv_number(*v) : std::string());
      }
      csv += "\n";
    }
    return csv;
  }
  // The progress matrix, one row per trainee and module.
  csv = "trainee_id,module_id,state,attempts,passes,consecutive_passes_at_end,required,"
        "best_score,last_score\n";
  for (const DashboardTrainee& t : model.trainees) {
    for (const ModuleProgress& p : t.progress) {
      csv += csv_text(t.info.id) + "," + csv_text(p.module_id) + "," + progress_state(p) + "," +
             std::to_string(p.run.attempts) + "," + std::to_string(p.run.passes) + "," +
             std::to_string(p.run.consecutive_at_end) + "," +
             std::to_string(p.required_consecutive) + "," + csv_optional(p.best_score) + "," +
             csv_optional(p.last_score) + "\n";
    }
  }
  return csv;
}

std::string dashboard_csv_name(const DashboardSelection& selection,
                               const AttemptDrillDown* attempt) {
  if (attempt && attempt->recording)
    return "dashboard-attempt-" + std::to_string(attempt->record.id) + ".csv";
  if (!selection.trainee_id.empty()) {
    std::string safe;
    for (char c : selection.trainee_id)
      safe += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
    return "dashboard-" + safe + ".csv";
  }
  return "dashboard-progress.csv";
}

}  // namespace acdr
