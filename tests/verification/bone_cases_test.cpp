// The bone finite-element verification cases in their fast form, with other parameters than
// their defaults, and the failures they must report (locking linear elements in bending).
#include <gtest/gtest.h>

#include "verification/verification_case.hpp"

namespace acdr {
namespace {

void expect_all_pass(const VerificationCaseSpec& spec) {
  ASSERT_FALSE(spec.kind.empty());
  const auto rows = run_verification_case(spec);
  ASSERT_FALSE(rows.empty());
  for (const auto& r : rows)
    EXPECT_TRUE(r.passed) << r.case_name << " / " << r.quantity << ": simulated " << r.simulated
                          << ", analytic " << r.analytic << ", rel_error " << r.rel_error << " > "
                          << r.tolerance << " " << r.note;
}

VerificationCaseSpec fast(const char* kind) {
  return default_verification_case(kind, true);
}

TEST(BoneVerification, CasesAreBuiltIn) {
  const auto kinds = verification_case_kinds();
  for (const char* k : {"bone_compression", "bone_cantilever", "bone_convergence"})
    EXPECT_NE(std::find(kinds.begin(), kinds.end(), k), kinds.end()) << k;
}

TEST(BoneVerification, CompressionIsExactForBothOrders) {
  auto s = fast("bone_compression");
  expect_all_pass(s);
  s.set("order", 2.0);
  s.set("youngs_modulus_Pa", 12e9);
  s.set("poisson_ratio", 0.45);
  s.set("height_m", 7e-3);
  expect_all_pass(s);
}

TEST(BoneVerification, CantileverMatchesBeamTheory) {
  expect_all_pass(fast("bone_cantilever"));
  auto s = fast("bone_cantilever");
  s.set("youngs_modulus_Pa", 3.5e9);
  s.set("poisson_ratio", 0.29);
  s.set("load_N", 0.2);
  expect_all_pass(s);
}

TEST(BoneVerification, LinearTetrahedraLockInBending) {
  // The same documented mesh with linear elements: far too stiff, and reported as a failure.
  auto s = fast("bone_cantilever");
  s.set("order", 1.0);
  const auto rows = run_verification_case(s);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_FALSE(rows[0].passed);
  EXPECT_LT(rows[0].simulated, 0.7 * rows[0].analytic);
}

TEST(BoneVerification, VertebraStressConvergesUnderAPatchLoad) {
  expect_all_pass(fast("bone_convergence"));
}

}  // namespace
}  // namespace acdr
