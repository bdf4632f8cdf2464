// `acdr make-trajectory`: a waypoint CSV sampled into a minimum-jerk trajectory CSV.
#include "cli/make_trajectory_command.hpp"

#include <fstream>
#include <ostream>
#include <sstream>

#include "engine/devices/waypoint_path.hpp"

namespace acdr {

int run_make_trajectory(const std::string& waypoints, const std::string& output, double rate_hz,
                        std::ostream& out, std::ostream& err) {
  std::ifstream in(waypoints, std::ios::binary);
  if (!in) {
    err << waypoints << ": cannot open waypoint file\n";
    return 2;
  }
  std::stringstream text;
  text << in.rdbuf();
  std::string error;
  const auto w = parse_waypoints(text.str(), waypoints, &error);
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
