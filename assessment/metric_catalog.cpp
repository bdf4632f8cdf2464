// The metric catalogue (definitions in docs/assessment.md).
#include "assessment/metric_catalog.hpp"

#include <algorithm>
#include <regex>

namespace acdr {

const std::vector<MetricInfo>& metric_catalog() {
  static const std::vector<MetricInfo> kCatalog = {
      {"nucleus_removed_mm3", "target material out of the removal region at the end (mm^3)"},
      {"nucleus_removed_fraction", "the same as a fraction of the initial target material"},
      {"protected_removed_mm3",
       "non-target material (annulus, endplate cartilage) removed: a safety penalty (mm^3)"},
      {"peak_instrument_force_N", "largest force of tissue and solids on the instrument (N)"},
      {"instrument_force_impulse_Ns", "time integral of that force over the attempt (N s)"},
      {"peak_contact_force_N",
       "largest rigid contact force on the instrument: bone (walls in the box) (N)"},
      {"peak_feedback_force_N", "largest force sent to the device (N)"},
      {"peak_bending_moment_Nm", "largest shaft bending moment at the grip (N m)"},
      {"yield_moment_Nm", "the shaft's yield moment, sigma_y pi d^3 / 32 (N m)"},
      {"overload_events", "crossings of the warning fraction of the yield moment"},
      {"yield_events", "crossings of the yield moment: the instrument bent"},
      {"time_over_warning_s", "time with the bending moment above the warning fraction (s)"},
      {"tip_path_length_mm", "distance travelled by the working tip (mm)"},
      {"duration_s", "simulated duration of the attempt (s)"},
      {"idle_time_s", "time with the tip slower than 1 mm/s (s)"},
      {"input_rejections", "runs of device samples rejected (NaN or jumps)"},
      {"force_clamped_events", "times the force to the device hit its maximum"},
      {"numerical_events", "numerical trouble reported by the simulation"},
      {"zone_warnings", "times the instrument came within a danger zone's warning distance"},
      {"zone_entries", "times the instrument entered a danger zone"},
      {"zone_over_limit_events", "times the force near a zone rose above the zone's limit"},
      {"zone_peak_force_N", "largest instrument force near any danger zone (N)"},
      {"zone_impulse_Ns", "sum over zones of the force-time impulse near them (N s)"},
      {"zone_dwell_s", "time within the warning distance of at least one zone (s)"},
      {"never_events", "entries into never-event zones (any fails the attempt)"},
  };
  return kCatalog;
}

const std::vector<MetricInfo>& lump_metric_catalog() {
  static const std::vector<MetricInfo> kCatalog = {
      {"removed_lump_fraction",
       "share of the removed particles in lumps (clusters of 10 or more) at the end"},
      {"removed_clusters", "clusters the removed particles form at the end (single ones too)"},
      {"removed_lumps", "clusters of 10 or more removed particles at the end"},
      {"removed_largest_cluster", "particles in the largest cluster of removed material"},
  };
  return kCatalog;
}

const std::vector<MetricInfo>& bone_metric_catalog() {
  static const std::vector<MetricInfo> kCatalog = {
      {"endplate_c4_peak_stress_MPa",
       "C4 inferior bony endplate: peak von Mises stress over the attempt (MPa)"},
      {"endplate_c5_peak_stress_MPa",
       "C5 superior bony endplate: peak von Mises stress over the attempt (MPa)"},
      {"endplate_peak_stress_MPa", "the larger of the two endplate peaks (MPa)"},
      {"posterior_peak_stress_MPa",
       "pedicles and bone around the foramina, C4 or C5: peak von Mises stress (MPa)"},
      {"endplate_time_over_warning_s",
       "time with an endplate's stress above the warning fraction of its strength (s)"},
      {"posterior_time_over_warning_s",
       "time with the pedicles' stress above the warning fraction of their strength (s)"},
      {"bone_peak_load_N", "largest total load on the bone in a sample: instrument and nucleus (N)"},
      {"bone_peak_load_time_s", "when that load was sampled (s into the attempt)"},
  };
  return kCatalog;
}

bool is_bone_metric_name(const std::string& name) {
  const auto& bone = bone_metric_catalog();
  return std::any_of(bone.begin(), bone.end(), [&](const MetricInfo& m) { return m.name == name; });
}

const std::vector<std::string>& known_metric_names() {
  static const std::vector<std::string> kNames = [] {
    std::vector<std::string> names;
    for (const MetricInfo& m : metric_catalog()) names.push_back(m.name);
    for (const MetricInfo& m : lump_metric_catalog()) names.push_back(m.name);
    for (const MetricInfo& m : bone_metric_catalog()) names.push_back(m.name);
    return names;
  }();
  return kNames;
}

const std::vector<MetricInfo>& zone_metric_catalog() {
  static const std::vector<MetricInfo> kCatalog = {
      {"peak_force_N", "largest instrument force while inside or within the warning distance (N)"},
      {"impulse_Ns", "time integral of that force while inside or within the warning distance (N s)"},
      {"dwell_s", "time inside or within the warning distance (s)"},
      {"inside_s", "time overlapping the zone (s)"},
      {"closest_mm", "closest instrument-zone distance, negative when overlapping (mm)"},
      {"warnings", "times the instrument came within the warning distance"},
      {"entries", "times the instrument entered the zone"},
      {"over_limit_events", "times the force near the zone rose above its limit"},
      {"never_event", "1 when the zone is a never-event zone and was entered, else 0"},
  };
  return kCatalog;
}

std::vector<std::string> zone_metric_ids(const std::vector<std::string>& zone_names) {
  std::vector<std::string> ids;
  ids.reserve(zone_names.size());
  for (std::size_t i = 0; i < zone_names.size(); ++i) {
    std::string id;
    bool gap = false;
    for (const char raw : zone_names[i]) {
      const char c = (raw >= 'A' && raw <= 'Z') ? static_cast<char>(raw - 'A' + 'a') : raw;
      const bool keep = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
      if (keep) {
        if (gap && !id.empty()) id += '_';
        id += c;
        gap = false;
      } else {
        gap = true;
      }
    }
    while (!id.empty() && id.front() == '_') id.erase(id.begin());
    while (!id.empty() && id.back() == '_') id.pop_back();
    if (id.empty()) id = "zone" + std::to_string(i);
    const std::string base = id;
    for (int n = 2; std::find(ids.begin(), ids.end(), id) != ids.end(); ++n)
      id = base + "_" + std::to_string(n);
    ids.push_back(id);
  }
  return ids;
}

std::string zone_metric_name(std::string_view zone_id, std::string_view quantity) {
  std::string name = "zone.";
  name += zone_id;
  name += '.';
  name += quantity;
  return name;
}

const std::string& zone_metric_pattern() {
  static const std::string kPattern = [] {
    std::string alternatives;
    for (const MetricInfo& q : zone_metric_catalog())
      alternatives += (alternatives.empty() ? "" : "|") + q.name;
    return "^zone\\.[a-z0-9_]+\\.(" + alternatives + ")$";
  }();
  return kPattern;
}

bool is_known_metric_name(const std::string& name) {
  const auto& fixed = known_metric_names();
  if (std::find(fixed.begin(), fixed.end(), name) != fixed.end()) return true;
  static const std::regex kZone(zone_metric_pattern(), std::regex::ECMAScript);
  return std::regex_match(name, kZone);
}

}  // namespace acdr
