// Materials per region and their checks.
#include "engine/bone/bone_material.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

TEST(BoneMaterial, ShellElementsMixByTheirShellFraction) {
  const BoneMaterials m;
  EXPECT_DOUBLE_EQ(element_material(m, BoneRegion::kCancellous, 0.7).youngs_modulus_Pa, 100e6);
  EXPECT_DOUBLE_EQ(element_material(m, BoneRegion::kPosterior, 0.7).youngs_modulus_Pa, 3.5e9);
  const IsotropicMaterial c = element_material(m, BoneRegion::kCortical, 0.25);
  EXPECT_DOUBLE_EQ(c.youngs_modulus_Pa, 0.25 * 12e9 + 0.75 * 100e6);
  EXPECT_DOUBLE_EQ(c.poisson_ratio, 0.3);
  const IsotropicMaterial e = element_material(m, BoneRegion::kEndplate, 1.0);
  EXPECT_DOUBLE_EQ(e.youngs_modulus_Pa, 1000e6);
  EXPECT_DOUBLE_EQ(e.poisson_ratio, 0.4);
}

TEST(BoneMaterial, ValidationNamesTheBadValue) {
  BoneMaterials m;
  EXPECT_EQ(validate_bone_materials(m), "");
  m.endplate.poisson_ratio = 0.5;
  m.cortical.youngs_modulus_Pa = -1.0;
  const std::string why = validate_bone_materials(m);
  EXPECT_NE(why.find("endplate.poisson_ratio"), std::string::npos) << why;
  EXPECT_NE(why.find("cortical.youngs_modulus_Pa"), std::string::npos) << why;
}

}  // namespace
}  // namespace acdr
