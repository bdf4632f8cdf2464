// Metric definitions (docs/assessment.md). Each is a plain reduction over the frames.
#include "assessment/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "assessment/metric_catalog.hpp"
#include "assessment/removed_lumps.hpp"

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

namespace {

// Per-zone reductions over the frames' zone samples (Frame::zones), and their sums over zones.
// "Near" a zone = inside it or within its warning distance: the force near it is what the
// instrument presses on the tissue there (the engine sets it to 0 elsewhere).
struct ZoneTotals {
  double peak_force = 0, impulse = 0, dwell = 0, inside = 0;
  double closest = std::numeric_limits<double>::quiet_NaN();
  int warnings = 0, entries = 0, over_limit = 0;
};

void add_zone_metrics(const AttemptRecording& record, Metrics& m) {
  const WorldSummary& s = record.summary;
  const std::size_t zones = std::min<std::size_t>(s.zones.size(), Frame::kZoneCapacity);
  std::vector<ZoneTotals> totals(zones);
  std::vector<std::uint8_t> was_inside(zones, 0), was_warning(zones, 0), was_over(zones, 0);
  double near_any = 0;
  for (const Frame& f : record.frames) {
    const std::size_t sampled = std::min<std::size_t>(zones, std::max(0, f.zone_count));
    bool near_one = false;
    for (std::size_t k = 0; k < sampled; ++k) {
      const Frame::ZoneState& z = f.zones[k];
      ZoneTotals& t = totals[k];
      const bool near = z.inside || z.warning;
      const double force = near ? static_cast<double>(z.force_N) : 0.0;
      const double distance_mm = static_cast<double>(z.distance_m) * 1e3;
      if (!(distance_mm >= t.closest)) t.closest = distance_mm;  // also replaces the NaN
      if (near) {
        t.peak_force = std::max(t.peak_force, force);
        t.impulse += force * s.dt_s;
        t.dwell += s.dt_s;
        near_one = true;
      }
      if (z.inside) t.inside += s.dt_s;
      // Rising edges, as the engine emits its zone events (engine/world/world.cpp).
      const bool over = z.warning && force > s.zones[k].force_limit_N;
      if (z.inside && !was_inside[k]) ++t.entries;
      if (z.warning && !was_warning[k]) ++t.warnings;
      if (over && !was_over[k]) ++t.over_limit;
      was_inside[k] = z.inside, was_warning[k] = z.warning, was_over[k] = over;
    }
    if (near_one) near_any += s.dt_s;
  }

  double peak = 0, impulse = 0;
  int warnings = 0, entries = 0, over_limit = 0, never = 0;
  for (std::size_t k = 0; k < zones; ++k) {
    const ZoneTotals& t = totals[k];
    peak = std::max(peak, t.peak_force);
    impulse += t.impulse;
    warnings += t.warnings, entries += t.entries, over_limit += t.over_limit;
    if (s.zones[k].never_event) never += t.entries;
  }
  m.set("zone_warnings", warnings);
  m.set("zone_entries", entries);
  m.set("zone_over_limit_events", over_limit);
  m.set("zone_peak_force_N", peak);
  m.set("zone_impulse_Ns", impulse);
  m.set("zone_dwell_s", near_any);
  m.set("never_events", never);

  std::vector<std::string> names;
  for (std::size_t k = 0; k < zones; ++k) names.push_back(s.zones[k].name);
  const std::vector<std::string> ids = zone_metric_ids(names);
  for (std::size_t k = 0; k < zones; ++k) {
    const ZoneTotals& t = totals[k];
    // Order as zone_metric_catalog(); appended directly (names are unique by construction).
    const double values[] = {t.peak_force,
                             t.impulse,
                             t.dwell,
                             t.inside,
                             t.closest,
                             static_cast<double>(t.warnings),
                             static_cast<double>(t.entries),
                             static_cast<double>(t.over_limit),
                             s.zones[k].never_event && t.entries > 0 ? 1.0 : 0.0};
    const auto& quantities = zone_metric_catalog();
    static_assert(std::size(values) == 9);
    for (std::size_t q = 0; q < quantities.size() && q < std::size(values); ++q)
      m.values.emplace_back(zone_metric_name(ids[k], quantities[q].name), values[q]);
  }
}

}  // namespace

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
      // Zone metrics are counted from the frames' zone samples (below), which the engine
      // never drops; the zone events are kept for the record and the dashboard.
      case EventKind::kZoneWarning:
      case EventKind::kZoneEntry:
      case EventKind::kNeverEvent:
      case EventKind::kZoneForce: break;
      // Which instrument is in hand is part of the record, not a score.
      case EventKind::kInstrumentExchange: break;
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
  add_zone_metrics(record, m);
  // How the removed material left, in lumps or scattered: after the zones' metrics, and only
  // when the record has where it lies at the end (lump_metric_catalog()).
  if (record.removed_positions) {
    const double spacing = std::cbrt(s.particle_volume_m3);
    const LumpStats lumps = removed_lumps(*record.removed_positions, kLumpLinkSpacings * spacing);
    m.set("removed_lump_fraction", lumps.lump_fraction());
    m.set("removed_clusters", lumps.clusters);
    m.set("removed_lumps", lumps.lumps);
    m.set("removed_largest_cluster", lumps.largest);
  }
  return m;
}

}  // namespace acdr
