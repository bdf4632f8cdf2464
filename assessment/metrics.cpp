// Metric definitions (docs/assessment.md). Each is a plain reduction over the frames.
#include "assessment/metrics.hpp"

#include <algorithm>

namespace acdr {

void Metrics::set(const std::string& name, double value) {
  for (auto& [n, v] : values)
    if (n == name) {
      v = value;
      return;
    }
  values.emplace_back(name, value);
}

const double* Metrics::find(const std::string& name) const {
  for (const auto& [n, v] : values)
    if (n == name) return &v;
  return nullptr;
}

Metrics compute_metrics(const AttemptRecording& record) {
  const WorldSummary& s = record.summary;
  Metrics m;
  const Frame* last = record.frames.empty() ? nullptr : &record.frames.back();
  const double to_mm3 = s.particle_volume_m3 * 1e9;

  // Material removed, judged at the end of the attempt.
  const double removed = last ? last->removed_target : 0;
  const double removed_protected = last ? last->removed_protected : 0;
  m.set("nucleus_removed_mm3", removed * to_mm3);
  m.set("nucleus_removed_fraction", s.initial_target > 0 ? removed / s.initial_target : 0.0);
  m.set("protected_removed_mm3", removed_protected * to_mm3);

  // Forces and moments over the attempt.
  double peak_force = 0, peak_contact = 0, peak_feedback = 0, peak_moment = 0;
  double time_over_warning = 0, path = 0, idle = 0, impulse = 0;
  for (std::size_t i = 0; i < record.frames.size(); ++i) {
    const Frame& f = record.frames[i];
    const double env = (f.nucleus_force_N + f.contact_force_N).norm();
    peak_force = std::max(peak_force, env);
    peak_contact = std::max(peak_contact, f.contact_force_N.norm());
    peak_feedback = std::max(peak_feedback, f.feedback_force_N.norm());
    peak_moment = std::max(peak_moment, f.bending_moment_Nm);
    impulse += env * s.dt_s;
    if (s.warning_moment_Nm > 0 && f.bending_moment_Nm > s.warning_moment_Nm)
      time_over_warning += s.dt_s;
    if (i > 0) {
      const double step = (f.tip_m - record.frames[i - 1].tip_m).norm();
      path += step;
      if (step < kIdleSpeed_m_s * s.dt_s) idle += s.dt_s;
    }
  }
  m.set("peak_instrument_force_N", peak_force);
  m.set("instrument_force_impulse_Ns", impulse);
  m.set("peak_contact_force_N", peak_contact);
  m.set("peak_feedback_force_N", peak_feedback);
  m.set("peak_bending_moment_Nm", peak_moment);
  m.set("yield_moment_Nm", s.yield_moment_Nm);

  int warnings = 0, yields = 0, rejected = 0, clamped = 0, numerical = 0;
  for (const Event& e : record.events) {
    switch (e.kind) {
      case EventKind::kOverloadWarning: ++warnings; break;
      case EventKind::kOverloadYield: ++yields; break;
      case EventKind::kInputRejected: ++rejected; break;
      case EventKind::kForceClamped: ++clamped; break;
      case EventKind::kNumerical: ++numerical; break;
      case EventKind::kAttemptEnd: break;
      // Device silence is a property of the setup, not of the trainee's skill: stored as
      // events, not scored.
      case EventKind::kInputLost: break;
      case EventKind::kDeviceDisconnected: break;
    }
  }
  m.set("overload_events", warnings);
  m.set("yield_events", yields);
  m.set("time_over_warning_s", time_over_warning);
  m.set("tip_path_length_mm", path * 1e3);
  m.set("duration_s", last ? last->t_s : 0.0);
  m.set("idle_time_s", idle);
  m.set("input_rejections", rejected);
  m.set("force_clamped_events", clamped);
  m.set("numerical_events", numerical);
  return m;
}

}  // namespace acdr
