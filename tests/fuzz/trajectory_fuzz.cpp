// libFuzzer target: the trajectory CSV reader on any bytes. A trajectory it accepts has finite
// numbers, a first time >= 0, strictly increasing times and unit quaternions.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "engine/devices/trajectory.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::string error;
  const auto t = acdr::Trajectory::parse_csv(text, "fuzz.csv", &error);
  if (!t) {
    if (error.rfind("fuzz.csv:", 0) != 0) std::abort();
    return 0;
  }
  double last = -1.0;
  for (const acdr::TrajectorySample& s : t->samples()) {
    if (!std::isfinite(s.t_s) || s.t_s < 0.0 || !(s.t_s > last)) std::abort();
    if (!s.pose.position.allFinite()) std::abort();
    if (!(std::fabs(s.pose.orientation.norm() - 1.0) < 1e-9)) std::abort();
    last = s.t_s;
  }
  return 0;
}
