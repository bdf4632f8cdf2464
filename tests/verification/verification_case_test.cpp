// Fast versions of the `acdr verify` cases (smaller scenes, same tolerances), plus each case
// with parameters other than its defaults: the model must be right, not tuned.
#include "verification/verification_case.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

void expect_all_pass(const VerificationCaseSpec& spec) {
  ASSERT_FALSE(spec.kind.empty());
  const auto rows = run_verification_case(spec);
  ASSERT_FALSE(rows.empty());
  for (const auto& r : rows)
    EXPECT_TRUE(r.passed) << r.case_name << " / " << r.quantity << ": simulated " << r.simulated
                          << ", analytic " << r.analytic << ", rel_error " << r.rel_error
                          << " > " << r.tolerance << " " << r.note;
}

VerificationCaseSpec fast(const char* kind) { return default_verification_case(kind, true); }

TEST(Verification, EveryAnalyticCaseIsBuiltIn) {
  const auto kinds = verification_case_kinds();
  for (const char* k : {"couette_shear", "buoyancy", "lever_feedback", "lift_equilibrium",
                        "bond_break", "lump_retention", "oscillator", "viscous_decay"})
    EXPECT_NE(std::find(kinds.begin(), kinds.end(), k), kinds.end()) << k;
}

TEST(Verification, CouetteShear) { expect_all_pass(fast("couette_shear")); }
TEST(Verification, CouetteShearOtherViscosityGapAndStep) {
  auto s = fast("couette_shear");
  s.set("viscosity_Pa_s", 1200.0);
  s.set("gap_m", 5e-3);
  s.set("dt_s", 2e-3);
  s.set("plate_speed_m_s", 0.03);
  s.set("duration_s", 0.1);  // the layers slide past each other by several h
  expect_all_pass(s);
}
TEST(Verification, Buoyancy) { expect_all_pass(fast("buoyancy")); }
TEST(Verification, LeverFeedback) { expect_all_pass(fast("lever_feedback")); }
TEST(Verification, LeverFeedbackOtherLeverAndMaterial) {
  auto s = fast("lever_feedback");
  s.set("viscosity_Pa_s", 100.0);
  s.set("pivot_distance_m", 0.015);
  s.set("prism_mass_kg", 0.02);
  expect_all_pass(s);
}
TEST(Verification, LiftEquilibrium) { expect_all_pass(fast("lift_equilibrium")); }
TEST(Verification, LiftEquilibriumSofterMaterialFasterLift) {
  auto s = fast("lift_equilibrium");
  s.set("bond_stiffness_N_m", 2.0);
  s.set("density_kg_m3", 1100.0);
  s.set("lift_speed_m_s", 0.02);
  expect_all_pass(s);
}
TEST(Verification, BondBreak) { expect_all_pass(fast("bond_break")); }
TEST(Verification, BondBreakStiffBonds) {
  auto s = fast("bond_break");
  s.set("bond_stiffness_N_m", 1e5);
  s.set("bond_break_m", 0.05e-3);
  expect_all_pass(s);
}
TEST(Verification, LumpRetention) { expect_all_pass(fast("lump_retention")); }
TEST(Verification, Oscillator) { expect_all_pass(fast("oscillator")); }
TEST(Verification, OscillatorStifferHeavier) {
  auto s = fast("oscillator");
  s.set("bond_stiffness_N_m", 80.0);
  s.set("density_kg_m3", 2000.0);
  s.set("dt_s", 4e-6);
  expect_all_pass(s);
}
TEST(Verification, ViscousDecay) { expect_all_pass(fast("viscous_decay")); }
TEST(Verification, ViscousDecayThinnerFluidLongerStep) {
  auto s = fast("viscous_decay");
  s.set("viscosity_Pa_s", 5.0);
  s.set("dt_s", 2e-5);
  expect_all_pass(s);
}

// The comparison can fail: a step far too coarse for the oscillation must be reported as a
// failure, not passed.
TEST(Verification, UnderResolvedOscillatorFails) {
  auto s = fast("oscillator");
  s.set("dt_s", 1e-3);
  const auto rows = run_verification_case(s);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_FALSE(rows[0].passed);
}

TEST(Verification, UnknownKindIsAFailedRow) {
  VerificationCaseSpec s;
  s.name = s.kind = "no_such_case";
  const auto rows = run_verification_case(s);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_FALSE(rows[0].passed);
}

}  // namespace
}  // namespace acdr
