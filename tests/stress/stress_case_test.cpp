// Fast versions of the `acdr stress` cases (2 mm spacing): no NaN, no energy growth with
// nothing driven, no particle through a wall, device force within its limit.
#include "stress/stress_case.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

namespace acdr {
namespace {

class StressCase : public ::testing::TestWithParam<StressCaseSpec> {};

TEST_P(StressCase, Passes) {
  const StressResult r = run_stress_case(GetParam());
  EXPECT_FALSE(r.nan) << r.nan_stage;
  EXPECT_FALSE(r.energy_grew) << "energy change " << r.hold_energy_change_J << " J";
  EXPECT_EQ(r.tunnelled, 0);
  EXPECT_LE(r.peak_device_force_N, r.device_limit_N * (1.0 + 1e-9));
  EXPECT_TRUE(r.passed);
  EXPECT_GT(r.particles, 0);
}

INSTANTIATE_TEST_SUITE_P(Fast, StressCase, ::testing::ValuesIn(builtin_stress_cases(true)),
                         [](const auto& info) {
                           std::string name = info.param.name;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

// The energy rule on synthetic hold series: growth (steady or exponential) fails, bounded
// jitter of any size passes.
TEST(StressSuite, EnergyRuleSeparatesGrowthFromJitter) {
  auto judge = [](auto energy, int n) {
    double early = 0, early2 = 0, late = 0;
    for (int k = 0; k < n; ++k) {
      const double e = energy(k);
      if (k < n / 2) {
        early += e;
        early2 += e * e;
      } else {
        late += e;
      }
    }
    const double m_early = early / (n / 2), m_late = late / (n - n / 2);
    const double jitter = std::sqrt(std::max(0.0, early2 / (n / 2) - m_early * m_early));
    return hold_energy_grew(m_late - m_early, 1e-7, jitter);
  };
  const double base = 1e-3;  // an offset, as gravity's potential gives
  EXPECT_TRUE(judge([&](int k) { return base + 1e-7 * std::exp2(k / 5.0); }, 50));
  EXPECT_TRUE(judge([&](int k) { return base + 1e-7 * k; }, 50));
  // Jitter 50x the kinetic energy, no trend: a square wave and a pseudo-random sequence.
  EXPECT_FALSE(judge([&](int k) { return base + ((k % 2) ? 5e-6 : -5e-6); }, 50));
  unsigned state = 12345;
  EXPECT_FALSE(judge([&](int) {
    state = state * 1103515245u + 12345u;
    return base + 5e-6 * (((state >> 16) & 0x7fff) / 16383.5 - 1.0);
  }, 400));
}

TEST(StressSuite, SweepsStepStiffnessViscositySpeedAndBadInput) {
  const auto cases = builtin_stress_cases(true);
  double dt_min = 1, dt_max = 0, k_max = 0, mu_min = 1e9, mu_max = 0, v_max = 0;
  bool teleport = false, bad = false;
  int every_max = 1;
  for (const auto& c : cases) {
    every_max = std::max(every_max, c.nucleus_every);
    dt_min = std::min(dt_min, c.dt_s);
    dt_max = std::max(dt_max, c.dt_s);
    k_max = std::max(k_max, c.bond_stiffness_N_m);
    mu_min = std::min(mu_min, c.viscosity_Pa_s);
    mu_max = std::max(mu_max, c.viscosity_Pa_s);
    v_max = std::max(v_max, c.speed_m_s);
    teleport = teleport || c.teleport;
    bad = bad || c.bad_input;
  }
  EXPECT_LE(dt_min, 0.25e-3);
  EXPECT_GE(dt_max, 4e-3);
  EXPECT_GE(k_max, 1e5);
  EXPECT_LE(mu_min, 1.0);
  EXPECT_GE(mu_max, 1e4);
  EXPECT_GE(v_max, 1.0);
  EXPECT_TRUE(teleport);
  EXPECT_TRUE(bad);
  EXPECT_GE(every_max, 10);  // the longest particle step the scenario format allows (10 ms)
}

}  // namespace
}  // namespace acdr
