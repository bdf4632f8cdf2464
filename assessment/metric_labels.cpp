// The label catalogue: see metric_labels.hpp.
#include "assessment/metric_labels.hpp"

#include <cctype>
#include <utility>
#include <vector>

namespace acdr {
namespace {

struct Entry {
  const char* id;
  const char* name;
  const char* unit;
};

// Fixed and bone metrics (metric_catalog.cpp), in catalogue order.
constexpr Entry kMetrics[] = {
    {"nucleus_removed_mm3", "Nucleus removed", "mm³"},
    {"nucleus_removed_fraction", "Nucleus removed (fraction)", ""},
    {"protected_removed_mm3", "Annulus and endplate removed", "mm³"},
    {"peak_instrument_force_N", "Peak instrument force", "N"},
    {"instrument_force_impulse_Ns", "Instrument force impulse", "N·s"},
    {"peak_contact_force_N", "Peak bone/wall contact force", "N"},
    {"peak_feedback_force_N", "Peak force on the hand", "N"},
    {"peak_bending_moment_Nm", "Peak shaft bending moment", "N·m"},
    {"yield_moment_Nm", "Shaft yield moment", "N·m"},
    {"overload_events", "Shaft overload warnings", ""},
    {"yield_events", "Shaft yield (bent) events", ""},
    {"time_over_warning_s", "Time over the overload warning", "s"},
    {"tip_path_length_mm", "Tip path length", "mm"},
    {"duration_s", "Duration", "s"},
    {"idle_time_s", "Idle time", "s"},
    {"input_rejections", "Device input rejected (runs)", ""},
    {"force_clamped_events", "Force limited to the device maximum (times)", ""},
    {"numerical_events", "Numerical trouble (times)", ""},
    {"zone_warnings", "Danger zone warnings", ""},
    {"zone_entries", "Danger zone entries", ""},
    {"zone_over_limit_events", "Force over a zone's limit (times)", ""},
    {"zone_peak_force_N", "Peak force near a danger zone", "N"},
    {"zone_impulse_Ns", "Force-time near danger zones", "N·s"},
    {"zone_dwell_s", "Time near danger zones", "s"},
    {"never_events", "Never-events", ""},
    {"removed_lump_fraction", "Removed material in lumps (fraction)", ""},
    {"removed_clusters", "Removed material: pieces", ""},
    {"removed_lumps", "Removed material: lumps of 10 or more", ""},
    {"removed_largest_cluster", "Removed material: largest piece (particles)", ""},
    {"endplate_c4_peak_stress_MPa", "C4 lower endplate: peak stress", "MPa"},
    {"endplate_c5_peak_stress_MPa", "C5 upper endplate: peak stress", "MPa"},
    {"endplate_peak_stress_MPa", "Endplates: peak stress", "MPa"},
    {"posterior_peak_stress_MPa", "Pedicles: peak stress", "MPa"},
    {"endplate_time_over_warning_s", "Endplates: time over the stress warning", "s"},
    {"posterior_time_over_warning_s", "Pedicles: time over the stress warning", "s"},
    {"bone_peak_load_N", "Peak load on the bone", "N"},
    {"bone_peak_load_time_s", "Time of the peak bone load", "s"},
};

// Per-zone quantities ("zone.<id>.<quantity>"), as read after the zone's name.
constexpr Entry kZoneQuantities[] = {
    {"peak_force_N", "peak force near it", "N"},
    {"impulse_Ns", "force-time near it", "N·s"},
    {"dwell_s", "time near it", "s"},
    {"inside_s", "time inside", "s"},
    {"closest_mm", "closest distance", "mm"},
    {"warnings", "warnings", ""},
    {"entries", "entries", ""},
    {"over_limit_events", "force over its limit (times)", ""},
    {"never_event", "never-event", ""},
};

const Entry* find(const Entry* begin, const Entry* end, const std::string& id) {
  for (const Entry* e = begin; e != end; ++e)
    if (id == e->id) return e;
  return nullptr;
}

std::string capitalised(std::string s) {
  if (!s.empty()) s[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(s[0])));
  return s;
}

// snake_case_with_unit -> {"Snake case with", "unit"}.
MetricLabel from_words(const std::string& metric) {
  static const std::pair<const char*, const char*> kUnits[] = {
      {"_mm3", "mm³"}, {"_MPa", "MPa"}, {"_mm", "mm"}, {"_Ns", "N·s"},
      {"_Nm", "N·m"},  {"_N", "N"},     {"_s", "s"},   {"_m", "m"}};
  std::string words = metric;
  std::string unit;
  for (const auto& [suffix_c, u] : kUnits) {
    const std::string suffix = suffix_c;
    if (words.size() > suffix.size() &&
        words.compare(words.size() - suffix.size(), suffix.size(), suffix) == 0) {
      unit = u;
      words.resize(words.size() - suffix.size());
      break;
    }
  }
  for (char& c : words)
    if (c == '_') c = ' ';
  return {capitalised(words), unit};
}

}  // namespace

std::string zone_display_name(const std::string& zone_name) {
  static const std::pair<const char*, const char*> kGenerated[] = {
      {"vertebral_artery_left", "left vertebral artery"},
      {"vertebral_artery_right", "right vertebral artery"},
      {"nerve_root_left", "left nerve root"},
      {"nerve_root_right", "right nerve root"},
      {"spinal_cord_pll", "spinal cord / PLL"},
      {"endplate_c4_lower", "C4 lower endplate"},
      {"endplate_c5_upper", "C5 upper endplate"},
  };
  for (const auto& [name, label] : kGenerated)
    if (zone_name == name) return label;
  return zone_name;
}

std::string zone_title(const std::string& zone_name) {
  return capitalised(zone_display_name(zone_name));
}

MetricLabel metric_label_parts(const std::string& metric) {
  if (const Entry* e = find(std::begin(kMetrics), std::end(kMetrics), metric))
    return {e->name, e->unit};
  // zone.<id>.<quantity> -> "<Zone>: <quantity>", e.g. "Spinal cord / PLL: peak force near it".
  if (metric.rfind("zone.", 0) == 0) {
    const std::size_t dot = metric.find('.', 5);
    if (dot != std::string::npos && dot + 1 < metric.size()) {
      std::string zone = zone_display_name(metric.substr(5, dot - 5));
      for (char& c : zone)
        if (c == '_') c = ' ';
      const std::string quantity = metric.substr(dot + 1);
      MetricLabel q;
      if (const Entry* e = find(std::begin(kZoneQuantities), std::end(kZoneQuantities), quantity))
        q = {e->name, e->unit};
      else
        q = from_words(quantity);
      if (!q.name.empty()) q.name[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(q.name[0])));
      return {capitalised(zone) + ": " + q.name, q.unit};
    }
  }
  return from_words(metric);
}

bool has_written_label(const std::string& metric) {
  if (find(std::begin(kMetrics), std::end(kMetrics), metric)) return true;
  if (metric.rfind("zone.", 0) != 0) return false;
  const std::size_t dot = metric.find('.', 5);
  return dot != std::string::npos &&
         find(std::begin(kZoneQuantities), std::end(kZoneQuantities), metric.substr(dot + 1));
}

std::string metric_label(const std::string& metric) {
  const MetricLabel l = metric_label_parts(metric);
  return l.unit.empty() ? l.name : l.name + " (" + l.unit + ")";
}

}  // namespace acdr
