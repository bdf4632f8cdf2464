// `acdr make-trajectory WAYPOINTS.csv OUT.csv`: a smooth device trajectory from waypoints.
#pragma once

#include <iosfwd>
#include <string>

namespace acdr {

int run_make_trajectory(const std::string& waypoints, const std::string& output, double rate_hz,
                        std::ostream& out, std::ostream& err);

}  // namespace acdr
