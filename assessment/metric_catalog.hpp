// The metrics assessment computes: names (with units in them), and what each means. Rubrics
// may refer only to these, so a misspelt metric never silently scores nothing.
//
// Two kinds of names:
// - fixed names, produced for every attempt (metric_catalog());
// - the lump metrics of the removed material, produced when the record holds where it lies at
//   the end (every attempt run since it is kept; lump_metric_catalog());
// - per-danger-zone names "zone.<zone-id>.<quantity>", produced for each zone of the scene
//   (zone_metric_catalog() lists the quantities). The zone id is the zone's name made safe:
//   zone_metric_ids().
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace acdr {

struct MetricInfo {
  std::string name;     ///< e.g. "peak_instrument_force_N"
  std::string meaning;  ///< one line, for documentation and the dashboard
};

/// Every fixed metric compute_metrics() produces, in its output order.
const std::vector<MetricInfo>& metric_catalog();

/// How the removed material left (assessment/removed_lumps.hpp), produced in this order after
/// the zones' metrics when the record has the removed particles' end positions.
const std::vector<MetricInfo>& lump_metric_catalog();

/// The bone-stress metrics, produced (in this order, after the fixed ones) only for a scene
/// whose bone is modelled as finite-element vertebrae (assessment/bone_metrics.hpp).
const std::vector<MetricInfo>& bone_metric_catalog();

/// Whether `name` is one of bone_metric_catalog().
bool is_bone_metric_name(const std::string& name);

/// The names a rubric may use by name: the fixed ones, the lump ones, then the bone ones, in
/// catalogue order.
const std::vector<std::string>& known_metric_names();

/// The per-zone quantities, in output order (name = the <quantity> part, e.g. "peak_force_N").
const std::vector<MetricInfo>& zone_metric_catalog();

/// Ids of the scene's zones for metric names, in zone order: each name lower-cased, every run
/// of characters other than [a-z0-9_] replaced by one '_', leading/trailing '_' dropped
/// ("Vertebral artery (L)" -> "vertebral_artery_l"); an empty result becomes "zone<index>";
/// a repeated id gets "_2", "_3", ... appended.
std::vector<std::string> zone_metric_ids(const std::vector<std::string>& zone_names);

/// "zone.<zone_id>.<quantity>".
std::string zone_metric_name(std::string_view zone_id, std::string_view quantity);

/// ECMAScript regular expression matching every per-zone metric name (anchored with ^ and $),
/// as the scenario schema states it.
const std::string& zone_metric_pattern();

/// Whether `name` is a fixed or bone metric or matches zone_metric_pattern().
bool is_known_metric_name(const std::string& name);

}  // namespace acdr
