// Derived quantities of the instrument description.
#include "engine/rigid/instrument_config.hpp"

#include <numbers>

namespace acdr {

double InstrumentConfig::yield_moment_Nm() const {
  // Elastic section modulus of a round shaft: M_yield = sigma_y * pi * d^3 / 32 (docs/references.md,
  // Assessment anchors; no published curette breaking load exists, so it is derived).
  return yield_stress_Pa * std::numbers::pi * shaft_diameter_m * shaft_diameter_m *
         shaft_diameter_m / 32.0;
}

}  // namespace acdr
