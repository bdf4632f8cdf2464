// Zone findings in words: see zone_findings.hpp.
#include "assessment/zone_findings.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "assessment/metric_catalog.hpp"

namespace acdr {
namespace {

// The zone ids of `metrics`, in their order, from the names "zone.<id>.dwell_s".
std::vector<std::string> ids_in(const Metrics& metrics) {
  std::vector<std::string> ids;
  const std::string prefix = "zone.", suffix = ".dwell_s";
  for (const auto& [name, value] : metrics.values) {
    if (name.size() <= prefix.size() + suffix.size() || name.rfind(prefix, 0) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    ids.push_back(name.substr(prefix.size(), name.size() - prefix.size() - suffix.size()));
  }
  return ids;
}

std::string describe(const ZoneFinding& f) {
  char text[256];
  const char* zone_word = f.label.find("zone") == std::string::npos ? " zone" : "";
  if (f.entered)
    std::snprintf(text, sizeof text, "entered the %s%s for %.1f s at up to %.3g N",
                  f.label.c_str(), zone_word, f.inside_s, f.peak_force_N);
  else
    std::snprintf(text, sizeof text, "came within %.2g mm of the %s%s for %.1f s at up to %.3g N",
                  std::max(0.0, f.closest_mm), f.label.c_str(), zone_word, f.dwell_s,
                  f.peak_force_N);
  std::string s = text;
  if (f.never_event) s += " (a never-event)";
  if (f.over_limit_events > 0) {
    std::snprintf(text, sizeof text, ", above its force limit %g time%s", f.over_limit_events,
                  f.over_limit_events == 1 ? "" : "s");
    s += text;
  }
  return s;
}

}  // namespace

std::vector<ZoneFinding> zone_findings(const Metrics& metrics,
                                       const std::vector<std::string>& zone_names) {
  const std::vector<std::string> ids = zone_names.empty() ? ids_in(metrics)
                                                          : zone_metric_ids(zone_names);
  auto value = [&](const std::string& id, const char* quantity) {
    const double* v = metrics.find(zone_metric_name(id, quantity));
    return v ? *v : 0.0;
  };
  std::vector<ZoneFinding> out;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    ZoneFinding f;
    f.id = ids[i];
    f.dwell_s = value(f.id, "dwell_s");
    f.entered = value(f.id, "entries") > 0;
    if (f.dwell_s <= 0.0 && !f.entered) continue;
    f.label = zone_display_name(zone_names.empty() ? f.id : zone_names[i]);
    f.never_event = value(f.id, "never_event") > 0;
    f.inside_s = value(f.id, "inside_s");
    f.peak_force_N = value(f.id, "peak_force_N");
    f.impulse_Ns = value(f.id, "impulse_Ns");
    f.closest_mm = value(f.id, "closest_mm");
    f.over_limit_events = value(f.id, "over_limit_events");
    f.text = describe(f);
    out.push_back(std::move(f));
  }
  std::stable_sort(out.begin(), out.end(), [](const ZoneFinding& a, const ZoneFinding& b) {
    if (a.entered != b.entered) return a.entered;
    if (a.never_event != b.never_event) return a.never_event;
    return a.dwell_s > b.dwell_s;
  });
  return out;
}

}  // namespace acdr
