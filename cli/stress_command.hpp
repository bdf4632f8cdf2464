// `acdr stress [--json] [--fast]`: the numerical stability stress suite (time step, bond
// stiffness, viscosity, instrument speed, a 5 cm teleport, NaN/Inf device input) run through
// the World; prints a table or {"cases": [{"name", "passed", ...figures}], "passed": bool}.
#pragma once

#include <ostream>

namespace acdr {

struct StressOptions {
  bool json = false;  ///< JSON on stdout instead of the table
  bool fast = false;  ///< 2 mm particle spacing and shorter holds (ctest)
};

/// Returns 0 when every case passes, 1 otherwise.
int run_stress(const StressOptions& options, std::ostream& out, std::ostream& err);

}  // namespace acdr
