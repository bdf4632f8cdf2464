// Material per tetrahedron and the checks on the material table.
#include "engine/bone/bone_material.hpp"

#include <string>

namespace acdr {

IsotropicMaterial element_material(const BoneMaterials& m, BoneRegion region,
                                   double shell_fraction) {
  auto mix = [&](const IsotropicMaterial& shell) {
    const double f = shell_fraction;
    return IsotropicMaterial{
        f * shell.youngs_modulus_Pa + (1.0 - f) * m.cancellous.youngs_modulus_Pa,
        f * shell.poisson_ratio + (1.0 - f) * m.cancellous.poisson_ratio};
  };
  switch (region) {
    case BoneRegion::kCancellous:
      return m.cancellous;
    case BoneRegion::kCortical:
      return mix(m.cortical);
    case BoneRegion::kEndplate:
      return mix(m.endplate);
    case BoneRegion::kPosterior:
      return m.posterior;
  }
  return m.cancellous;
}

IsotropicMaterial stress_material(const BoneMaterials& m, BoneRegion region) {
  switch (region) {
    case BoneRegion::kCancellous:
      return m.cancellous;
    case BoneRegion::kCortical:
      return m.cortical;
    case BoneRegion::kEndplate:
      return m.endplate;
    case BoneRegion::kPosterior:
      return m.posterior;
  }
  return m.cancellous;
}

std::string validate_bone_materials(const BoneMaterials& m) {
  std::string out;
  auto check = [&](const char* name, const IsotropicMaterial& x) {
    if (!(x.youngs_modulus_Pa > 0.0))
      out += std::string(name) + ".youngs_modulus_Pa: got " + std::to_string(x.youngs_modulus_Pa) +
             ", expected > 0\n";
    if (!(x.poisson_ratio >= 0.0 && x.poisson_ratio < 0.5))
      out += std::string(name) + ".poisson_ratio: got " + std::to_string(x.poisson_ratio) +
             ", expected 0 to 0.5 (exclusive)\n";
  };
  check("cortical", m.cortical);
  check("cancellous", m.cancellous);
  check("endplate", m.endplate);
  check("posterior", m.posterior);
  if (!(m.shell.cortical_thickness_m > 0.0))
    out += "shell.cortical_thickness_m: got " + std::to_string(m.shell.cortical_thickness_m) +
           ", expected > 0\n";
  if (!(m.shell.endplate_thickness_m > 0.0))
    out += "shell.endplate_thickness_m: got " + std::to_string(m.shell.endplate_thickness_m) +
           ", expected > 0\n";
  return out;
}

}  // namespace acdr
