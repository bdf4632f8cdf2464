// The metric catalogue (definitions in docs/assessment.md).
#include "assessment/metric_catalog.hpp"

namespace acdr {

const std::vector<MetricInfo>& metric_catalog() {
  static const std::vector<MetricInfo> kCatalog = {
      {"nucleus_removed_mm3", "target material out of the removal region at the end (mm^3)"},
      {"nucleus_removed_fraction", "the same as a fraction of the initial target material"},
      {"protected_removed_mm3", "non-target material (annulus) removed: a safety penalty (mm^3)"},
      {"peak_instrument_force_N", "largest force of tissue and solids on the instrument (N)"},
      {"instrument_force_impulse_Ns", "time integral of that force over the attempt (N s)"},
      {"peak_contact_force_N", "largest rigid (bone, wall) contact force on the instrument (N)"},
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
  };
  return kCatalog;
}

const std::vector<std::string>& known_metric_names() {
  static const std::vector<std::string> kNames = [] {
    std::vector<std::string> names;
    for (const MetricInfo& m : metric_catalog()) names.push_back(m.name);
    return names;
  }();
  return kNames;
}

}  // namespace acdr
