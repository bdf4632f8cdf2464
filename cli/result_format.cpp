// Result formatting.
#include "cli/result_format.hpp"

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "app/score_table.hpp"
#include "cli/send_command.hpp"
#include "assessment/metric_catalog.hpp"
#include "assessment/zone_findings.hpp"
#include "engine/core/state_hash.hpp"

namespace acdr {
namespace {

// The parts of a session's result every line below reads.
struct ResultView {
  const ScenarioModel& scenario;
  const AttemptRun& run;
  const World& world;
};

// The instruments in hand over the attempt, for a scene with a tray (world.instruments): the
// first from the start, then each exchange from its time. Empty for a scene of one instrument.
std::vector<std::pair<double, std::string>> instruments_in_hand(const ResultView& c) {
  std::vector<std::pair<double, std::string>> out;
  if (c.scenario.world.instruments.empty()) return out;
  out.emplace_back(0.0, c.scenario.world.instruments.front().name);
  for (const Event& e : c.run.record.events)
    if (e.kind == EventKind::kInstrumentExchange) out.emplace_back(e.t_s, e.detail);
  return out;
}

}  // namespace

nlohmann::json haptics_json(const HapticsReport& h, const AttemptRun& run) {
  int clamped = 0, lost = 0, rejected = 0;
  double max_feedback = 0.0;
  for (const Event& e : run.record.events) {
    clamped += e.kind == EventKind::kForceClamped;
    lost += e.kind == EventKind::kInputLost;
    rejected += e.kind == EventKind::kInputRejected;
  }
  for (const Frame& f : run.record.frames)
    max_feedback = std::max(max_feedback, f.feedback_force_N.norm());
  nlohmann::json j;
  j["rate_hz"] = h.loop.rate_hz;
  j["target_rate_hz"] = h.loop.target_rate_hz;
  j["period_mean_ms"] = h.loop.period_mean_ms;
  j["period_p99_ms"] = h.loop.period_p99_ms;
  j["period_max_ms"] = h.loop.period_max_ms;
  j["step_mean_ms"] = h.loop.work_mean_ms;
  j["step_p99_ms"] = h.loop.work_p99_ms;
  j["overruns"] = h.loop.overruns;
  j["resyncs"] = h.loop.resyncs;
  j["ticks"] = h.loop.ticks;
  j["realtime_priority"] = h.loop.realtime;
  j["packets_lost"] = h.has_link ? h.link.packets_lost : 0;
  j["force_clamped_events"] = clamped;
  j["input_lost_events"] = lost;
  j["input_rejected_events"] = rejected;
  // What actually left for the device: the link's own count when there is one.
  j["max_force_sent_N"] = h.has_link ? h.link.max_force_sent_N : max_feedback;
  j["device_max_force_N"] = run.record.summary.device_max_force_N;
  if (h.decoupled) {
    // The physics loop, paced at the scenario's rate: below it when a step costs more than
    // its period (the device loop above keeps its rate regardless).
    j["physics"] = {{"rate_hz", h.physics.rate_hz},
                    {"target_rate_hz", h.physics.target_rate_hz},
                    {"step_mean_ms", h.physics.work_mean_ms},
                    {"step_p99_ms", h.physics.work_p99_ms},
                    {"step_max_ms", h.physics.work_max_ms},
                    {"period_max_ms", h.physics.period_max_ms},
                    {"overruns", h.physics.overruns},
                    {"resyncs", h.physics.resyncs},
                    {"ticks", h.physics.ticks}};
    j["device_ticks_clamped"] = h.device_ticks_clamped;
    j["device_ticks_zeroed"] = h.device_ticks_zeroed;
  }
  j["decoupled"] = h.decoupled;
  if (h.has_link) {
    j["link"] = {{"bridge", h.link.bridge},
                 {"packets_received", h.link.packets_received},
                 {"packets_late", h.link.packets_late},
                 {"packets_malformed", h.link.packets_malformed},
                 {"packets_foreign", h.link.packets_foreign},
                 {"last_foreign", h.link.last_foreign},
                 {"forces_sent", h.link.forces_sent},
                 {"send_errors", h.link.send_errors},
                 {"silences", h.link.silences},
                 {"longest_silence_s", h.link.longest_silence_s},
                 {"end_of_attempt", h.link.end_of_attempt},
                 {"disconnected", h.link.disconnected}};
  }
  return j;
}

nlohmann::json result_json(const SessionResult& result, const std::string& png_path) {
  const ResultView c{*result.scenario, result.run, *result.world};
  nlohmann::json j;
  j["scenario"] = c.scenario.path;
  j["scenario_hash"] = c.scenario.hash;
  j["module"] = c.scenario.id;
  j["program_version"] = ACDR_VERSION_STRING;
  j["duration_s"] = c.world.time_s();
  j["steps"] = c.world.step_count();
  j["dt_s"] = c.scenario.world.solver.dt_s;
  j["end"] = attempt_end_name(c.run.end);
  j["wall_s"] = c.run.wall_s;
  j["realtime_factor"] = c.run.wall_s > 0 ? c.world.time_s() / c.run.wall_s : 0.0;
  j["state_hash"] = hash_hex(c.run.state_hash);
  // Solver figures: how hard the step worked (mean over the attempt).
  double iterations = 0, active = 0;
  int max_iterations = 0;
  for (const Frame& f : c.run.record.frames) {
    iterations += f.solver_iterations;
    active += f.active_particles;
    max_iterations = std::max(max_iterations, static_cast<int>(f.solver_iterations));
  }
  const double frames = std::max<double>(1.0, static_cast<double>(c.run.record.frames.size()));
  const StageTimes& times = c.world.stage_times();
  nlohmann::json stages = nlohmann::json::object();
  for (int s = 0; s < static_cast<int>(StepStage::kCount); ++s)
    stages[step_stage_name(static_cast<StepStage>(s))] =
        times.steps > 0 ? 1e3 * times.seconds[s] / static_cast<double>(times.steps) : 0.0;
  j["solver"] = {{"mean_iterations", iterations / frames},
                 {"max_iterations", max_iterations},
                 {"mean_active_particles", active / frames},
                 {"particles", c.world.nucleus() ? c.world.nucleus()->particle_count() : 0},
                 {"stage_ms_per_step", stages}};
  nlohmann::json metrics = nlohmann::json::object();
  for (const auto& [name, value] : c.run.metrics.values) metrics[name] = value;
  j["metrics"] = metrics;
  j["score"] = c.run.score.score;
  j["passed"] = c.run.score.passed;
  nlohmann::json terms = nlohmann::json::array();
  for (const TermScore& t : c.run.score.terms)
    terms.push_back({{"metric", t.metric}, {"value", t.value}, {"score", t.score}});
  j["terms"] = terms;
  nlohmann::json gates = nlohmann::json::array();
  for (const GateResult& g : c.run.score.gates)
    gates.push_back(
        {{"metric", g.metric}, {"value", g.value}, {"max", g.max}, {"passed", g.passed}});
  j["gates"] = gates;
  j["reasons"] = c.run.score.reasons;
  if (const auto used = instruments_in_hand(c); !used.empty()) {
    nlohmann::json in_hand = nlohmann::json::array();
    for (const auto& [t, name] : used) in_hand.push_back({{"from_s", t}, {"name", name}});
    j["instruments"] = in_hand;
  }
  nlohmann::json events = nlohmann::json::array();
  for (const Event& e : c.run.record.events)
    events.push_back({{"t_s", e.t_s}, {"kind", event_kind_name(e.kind)}, {"value", e.value},
                      {"detail", e.detail}});
  j["events"] = events;
  if (result.haptics) j["haptics"] = haptics_json(*result.haptics, c.run);
  if (c.run.bone_modelled) {
    // The bone's solver thread (docs/bone-fem.md, "In an attempt"): wall times per sample.
    const BoneWorkerStats& b = c.run.bone_stats;
    j["bone"] = {{"build_s", b.build_s},
                 {"samples", b.samples},
                 {"recorded_samples", c.run.record.bone_loads.size()},
                 {"solves", b.solves},
                 {"mean_sample_ms", b.mean_sample_ms},
                 {"max_sample_ms", b.max_sample_ms},
                 {"mean_sample_cpu_ms", b.mean_sample_cpu_ms},
                 {"mean_solve_cpu_ms", b.mean_solve_cpu_ms},
                 {"max_lag_s", b.lag_s},
                 {"background_priority", b.background_priority},
                 {"error", c.run.bone_error}};
  }
  j["stored_as"] = result.stored_as;
  j["attempt_id"] = result.attempt_id;
  j["db"] = result.db_path;
  if (!result.unsaved_file.empty()) j["unsaved_file"] = result.unsaved_file;
  if (!png_path.empty()) j["png"] = png_path;
  if (result.delivery) {
    const DeliveryReport& d = *result.delivery;
    j["lrs"] = {{"endpoint", d.endpoint},
                {"stored", d.stored},
                {"already_stored", d.already_stored},
                {"refused", d.rejected},
                {"queued", d.left.queued},
                {"stopped", d.stopped.empty() ? d.record_error : d.stopped}};
  }
  if (result.checkpoints) {
    // What the checkpoints cost: on the writer thread per checkpoint, and on the physics
    // thread per hand-over (haptics.physics has the physics loop's step times).
    const LiveCheckpointStats& s = result.checkpoints->stats;
    j["checkpoints"] = {{"every_s", result.checkpoints->every_s},
                        {"saved", s.saved},
                        {"failed", s.failed},
                        {"deferred", s.deferred},
                        {"frames_saved", s.frames_saved},
                        {"largest_frames", s.largest_frames},
                        {"write_mean_ms", s.write_mean_ms},
                        {"write_max_ms", s.write_max_ms},
                        {"handover_max_ms", s.handover_max_ms},
                        {"writer_background_priority", s.background_priority}};
  }
  return j;
}

std::string result_summary(const SessionResult& result, const std::string& png_path) {
  const ResultView c{*result.scenario, result.run, *result.world};
  std::string s;
  char line[256];
  auto metric = [&](const char* name) {
    const double* v = c.run.metrics.find(name);
    return v ? *v : 0.0;
  };
  std::snprintf(line, sizeof line, "%s  (%s)\n", c.scenario.title.c_str(),
                c.scenario.path.c_str());
  s += line;
  std::snprintf(line, sizeof line,
                "  simulated %.2f s in %.2f s wall (%.2fx real time), %lld steps of %.3g ms; "
                "ended: %s\n",
                c.world.time_s(), c.run.wall_s,
                c.run.wall_s > 0 ? c.world.time_s() / c.run.wall_s : 0.0,
                static_cast<long long>(c.world.step_count()), c.scenario.world.solver.dt_s * 1e3,
                attempt_end_name(c.run.end));
  s += line;
  std::snprintf(line, sizeof line, "  nucleus removed        %8.1f mm^3  (%.1f %% of the nucleus)\n",
                metric("nucleus_removed_mm3"), 100.0 * metric("nucleus_removed_fraction"));
  s += line;
  std::snprintf(line, sizeof line, "  peak instrument force  %8.3f N\n",
                metric("peak_instrument_force_N"));
  s += line;
  std::snprintf(line, sizeof line,
                "  peak bending moment    %8.4f N·m (yield %.3f N·m), overload events: %g\n",
                metric("peak_bending_moment_Nm"), metric("yield_moment_Nm"),
                metric("overload_events"));
  s += line;
  std::snprintf(line, sizeof line, "  tip path               %8.1f mm\n",
                metric("tip_path_length_mm"));
  s += line;
  if (const auto used = instruments_in_hand(c); !used.empty()) {
    s += "  instruments           ";
    for (std::size_t k = 0; k < used.size(); ++k) {
      std::snprintf(line, sizeof line, " %s from %.2f s", used[k].second.c_str(), used[k].first);
      s += std::string(k > 0 ? "," : "") + line;
    }
    s += "\n";
  }
  // Danger zones: totals, then each zone that was approached.
  const auto& zones = c.run.record.summary.zones;
  if (!zones.empty()) {
    std::snprintf(line, sizeof line,
                  "  danger zones           %8g warnings, %g entries, %g never-events; peak force "
                  "near a zone %.3f N, %.2f s near one\n",
                  metric("zone_warnings"), metric("zone_entries"), metric("never_events"),
                  metric("zone_peak_force_N"), metric("zone_dwell_s"));
    s += line;
    std::vector<std::string> names;
    for (const auto& z : zones) names.push_back(z.name);
    // Each zone approached, in words, with its figures.
    for (const ZoneFinding& f : zone_findings(c.run.metrics, names)) {
      s += "    " + f.text + "\n";
      std::snprintf(line, sizeof line,
                    "      (closest %.2f mm, %.2f s near, %.2f s inside, impulse %.4f N·s)\n",
                    f.closest_mm, f.dwell_s, f.inside_s, f.impulse_Ns);
      s += line;
    }
  }
  s += "  score by metric (S: a safety term):\n";
  for (const ScoreTableRow& row :
       score_table(c.run.metrics, c.run.score, &c.scenario.rubric, ScoreTableScope::kAssessed)) {
    if (row.judgement == MetricJudgement::kScored)
      std::snprintf(line, sizeof line, "    %s %-26s %10.4g  -> %5.1f / 100  (%s)\n",
                    row.safety ? "S" : " ", row.metric.c_str(), row.value, row.score,
                    benchmark_text(row).c_str());
    else
      std::snprintf(line, sizeof line, "    gate %-23s %10.4g  (max %g) %s\n",
                    row.metric.c_str(), row.value, row.gate_max, row.good ? "ok" : "FAILED");
    s += line;
  }
  std::snprintf(line, sizeof line, "  SCORE %.1f / 100 (pass at %.0f): %s\n", c.run.score.score,
                c.scenario.rubric.pass_score, c.run.score.passed ? "PASSED" : "NOT PASSED");
  s += line;
  for (const std::string& r : c.run.score.reasons) s += "    - " + r + "\n";
  s += "  how to read it:\n";
  for (const std::string& r : score_scale_text(&c.scenario.rubric)) s += "    " + r + "\n";
  if (result.haptics) {
    const HapticLoopStats& h = result.haptics->loop;
    std::snprintf(line, sizeof line,
                  "  haptic loop            %8.1f Hz (target %.0f), period p99 %.3f ms, "
                  "%lld overruns\n",
                  h.rate_hz, h.target_rate_hz, h.period_p99_ms, static_cast<long long>(h.overruns));
    s += line;
    if (result.haptics->decoupled) {
      const HapticLoopStats& p = result.haptics->physics;
      std::snprintf(line, sizeof line,
                    "  physics loop           %8.1f Hz (target %.0f), step mean %.3f ms, p99 "
                    "%.3f ms, max %.3f ms\n",
                    p.rate_hz, p.target_rate_hz, p.work_mean_ms, p.work_p99_ms, p.work_max_ms);
      s += line;
    }
    if (result.haptics->has_link) {
      const UdpDeviceStats& l = result.haptics->link;
      std::snprintf(line, sizeof line,
                    "  bridge %s: %lld packets, %lld lost, %lld malformed, %lld from other "
                    "senders (ignored), max force sent %.3f N\n",
                    l.bridge.c_str(), static_cast<long long>(l.packets_received),
                    static_cast<long long>(l.packets_lost),
                    static_cast<long long>(l.packets_malformed),
                    static_cast<long long>(l.packets_foreign), l.max_force_sent_N);
      s += line;
    }
  }
  std::snprintf(line, sizeof line, "  stored as attempt %lld (%s) in %s\n",
                static_cast<long long>(result.attempt_id), result.stored_as.c_str(),
                result.db_path.c_str());
  s += line;
  if (!result.unsaved_file.empty())
    s += "  result kept in " + result.unsaved_file + " until the record can be written\n";
  if (!png_path.empty()) s += "  picture of the final frame: " + png_path + "\n";
  if (result.delivery) s += "  xAPI statements " + delivery_summary(*result.delivery);
  if (result.checkpoints) {
    const LiveCheckpointStats& k = result.checkpoints->stats;
    std::snprintf(line, sizeof line,
                  "  checkpoints            %lld saved every %g s (writer thread: mean %.1f "
                  "ms, max %.1f ms; %lld deferred)\n",
                  static_cast<long long>(k.saved), result.checkpoints->every_s, k.write_mean_ms,
                  k.write_max_ms, static_cast<long long>(k.deferred));
    s += line;
  }
  return s;
}

}  // namespace acdr
