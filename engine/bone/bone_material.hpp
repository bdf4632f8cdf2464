// Linear elastic bone: isotropic materials per region from published cervical finite-element
// models (docs/bone-fem.md, Materials), and the mix used for the thin shell in elements thicker
// than it.
#pragma once

#include <string>

#include "engine/bone/bone_regions.hpp"

namespace acdr {

/// Young's modulus (Pa) and Poisson's ratio of an isotropic linear elastic solid.
struct IsotropicMaterial {
  double youngs_modulus_Pa = 0.0;
  double poisson_ratio = 0.0;
};

/// Defaults: cortical 12 GPa / 0.3 and bony endplate 1000 MPa (J Orthop Surg Res 2021, doi
/// 10.1186/s13018-021-02237-4; BioMed Eng OnLine 2014;13:115 uses 10 GPa / 0.29 and 500 MPa);
/// cancellous 100 MPa / 0.3 (both); posterior elements 3.5 GPa / 0.29 (BioMed Eng OnLine 2014).
/// The endplate's Poisson's ratio is 0.4 in both.
struct BoneMaterials {
  IsotropicMaterial cortical{12.0e9, 0.3};
  IsotropicMaterial cancellous{100.0e6, 0.3};
  IsotropicMaterial endplate{1000.0e6, 0.4};
  IsotropicMaterial posterior{3.5e9, 0.29};
  BoneShellParams shell;
};

/// The material of a tetrahedron. Shell tetrahedra (cortical, endplate) are part shell, part
/// cancellous bone: their stiffness is the volume-weighted mean (Voigt) of the two with the
/// tetrahedron's shell fraction, which keeps the shell's in-plane stiffness (modulus times
/// thickness) whatever the element size.
IsotropicMaterial element_material(const BoneMaterials& materials, BoneRegion region,
                                   double shell_fraction);

/// The material whose stress is reported for a tetrahedron: the shell's own (cortical or
/// endplate) for shell tetrahedra, so their stress is the stress in the cortex or the bony
/// endplate at the element's strain, not a mean over shell and core that would change with the
/// element size; the element's material otherwise.
IsotropicMaterial stress_material(const BoneMaterials& materials, BoneRegion region);

/// "" when every modulus is positive and every Poisson's ratio in [0, 0.5), else one line per
/// bad value, e.g. "cortical.poisson_ratio: got 0.5, expected 0 to 0.5 (exclusive)".
std::string validate_bone_materials(const BoneMaterials& materials);

}  // namespace acdr
