// What happened near the danger zones, in words a trainee reads on the score screen and in the
// terminal summary: "entered the spinal cord / PLL zone for 1.7 s at up to 1.4 N". Read from
// the per-zone metrics (zone.<id>.<quantity>, metric_catalog.hpp), so a stored attempt says the
// same as a live one.
#pragma once

#include <string>
#include <vector>

#include "assessment/attempt_result.hpp"
#include "assessment/metric_labels.hpp"  // zone_display_name

namespace acdr {

/// One zone the instrument came near (within its warning distance) or entered.
struct ZoneFinding {
  std::string id;     ///< metric id, e.g. "spinal_cord_pll"
  std::string label;  ///< zone_display_name of the zone's name
  bool entered = false;      ///< entries > 0
  bool never_event = false;  ///< a never-event zone that was entered
  double inside_s = 0.0;
  double dwell_s = 0.0;       ///< time near it (inside or within the warning distance)
  double peak_force_N = 0.0;  ///< largest instrument force near it
  double impulse_Ns = 0.0;
  double closest_mm = 0.0;  ///< negative: depth of overlap
  double over_limit_events = 0.0;
  std::string text;  ///< "entered the spinal cord / PLL zone for 1.7 s at up to 1.4 N"
};

/// The zones of `metrics` the instrument came near, entered ones first (never-events first of
/// those), then by time near them. `zone_names`: the scene's zone names in zone order (the
/// recording's); empty: the zone ids found in `metrics` stand for their names.
std::vector<ZoneFinding> zone_findings(const Metrics& metrics,
                                       const std::vector<std::string>& zone_names = {});

}  // namespace acdr
