// What a person reads for a metric or a danger zone: the one catalogue of human names and units
// that the HUD, the score screen, the terminal summary, the dashboard and the reports share.
// Metric ids (metric_catalog.hpp) stay the machine names in files, rubrics and exports; these
// labels are for screens and printed tables only.
#pragma once

#include <string>

namespace acdr {

/// A metric's name in words and its unit as printed ("" when it is a count or a fraction).
struct MetricLabel {
  std::string name;  ///< "Peak instrument force", "Left vertebral artery: time near it"
  std::string unit;  ///< "N", "mm³", "s", ""
};

/// The label of a fixed, bone or per-zone metric id ("zone.<id>.<quantity>"); an id outside
/// the catalogue gets words made from its snake_case, with a unit suffix (_mm3, _N, _s, ...)
/// read as its unit.
MetricLabel metric_label_parts(const std::string& metric);

/// Whether the catalogue has a written label for `metric` (a fixed or bone id, or a per-zone
/// id with a known quantity), rather than words made from the id.
bool has_written_label(const std::string& metric);

/// "Name (unit)", or "Name" without a unit: "Peak instrument force (N)".
std::string metric_label(const std::string& metric);

/// The name a person reads for a zone: the generated C4-C5 zones by their anatomy
/// ("spinal_cord_pll" -> "spinal cord / PLL", "nerve_root_left" -> "left nerve root"); any other
/// zone by its name as the scenario wrote it.
std::string zone_display_name(const std::string& zone_name);

/// The same with a capital first letter, to start a line: "Spinal cord / PLL".
std::string zone_title(const std::string& zone_name);

}  // namespace acdr
