// `acdr make-trajectory`: a waypoint CSV sampled into a minimum-jerk trajectory CSV.
#include "cli/make_trajectory_command.hpp"

#include <ostream>

#include "engine/core/input_file.hpp"
#include "engine/devices/waypoint_path.hpp"

namespace acdr {

int run_make_trajectory(const std::string& waypoints, const std::string& output, double rate_hz,
                        std::ostream& out, std::ostream& err) {
  std::string error;
  const auto text = read_input_file(waypoints, kMaxWaypointFileBytes, "a waypoint file (CSV)", &error);
  if (!text) {
    err << waypoints << ": " << error << "\n";
    return 2;
  }
  const auto w = parse_waypoints(*text, waypoints, &error);
  if (!w) {
    err << error << "\n";
    return 2;
  }
  const Trajectory t = sample_waypoints(*w, rate_hz);
  if (!t.save_csv(output, &error)) {
    err << error << "\n";
    return 2;
  }
  out << "wrote " << output << ": " << t.samples().size() << " samples over " << t.duration_s()
      << " s at " << rate_hz << " Hz\n";
  return 0;
}

}  // namespace acdr
