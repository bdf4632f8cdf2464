// The list of metric names rubrics may use, in the order the result JSON prints them.
#include "scenarios/known_metrics.hpp"

namespace acdr {

const std::vector<std::string>& known_metric_names() {
  static const std::vector<std::string> kNames = {
      "nucleus_removed_mm3",       // mm^3 of target material out of the removal region
      "nucleus_removed_fraction",  // the same as a fraction of the initial target material
      "peak_instrument_force_N",   // largest coupling force magnitude on the instrument
      "peak_bending_moment_Nm",    // largest shaft bending moment at the grip
      "overload_events",           // crossings of the warning fraction of the yield moment
  };
  return kNames;
}

}  // namespace acdr
