// Surface tension between torn faces of a material: the pair law. A gel torn by the curette
// keeps a surface energy where it was cut; two pieces that come near again pull together, so
// a load lifted out holds together and a strand drips as a strand, not as beads. It acts
// between two particles of one material with a surface tension (MaterialConfig::
// surface_tension_N_m) that no built bond joins (a broken one, or none: the pieces of a cut),
// as an attraction F(r) along the pair that is zero at the lattice spacing h and at its reach R
// and peaks between them. The reach is the bond radius (or the interaction radius if that is
// shorter): every pair of the intact lattice closer than the bond radius is bonded, so the
// intact material feels none of it, only the faces of a cut do.
//
//   F(r) = F_c sin(pi (r - h) / L),  h < r < R,  L = R - h,
//
// with F_c chosen so that separating the pair from h to R takes the work of making two faces
// of area h^2: integral of F over (h, R) = 2 gamma h^2, i.e. F_c = pi gamma h^2 / L. Its
// potential is U(r) = -F_c (L / pi) (1 + cos(pi (r - h) / L)) (constant -2 F_c L / pi below h,
// 0 beyond R), so the force is conservative and the energy balance includes it
// (Nucleus::mechanical_energy_J). The step treats the rising part of F implicitly (its
// stiffness F' > 0 joins the pair coefficient, keeping the system positive definite) and the
// falling part explicitly (a softening, stable at any step). docs/scenario-format.md,
// "Surface tension".
#pragma once

#include <cmath>
#include <numbers>

namespace acdr::nucleus {

/// F_c, the peak pair force (N), for surface tension gamma (N/m) on a lattice of spacing h with
/// reach R (m); 0 when R <= h (no room between touching and out of reach).
inline double surface_tension_peak_force(double gamma_N_m, double h, double R) {
  return (gamma_N_m > 0.0 && R > h) ? std::numbers::pi * gamma_N_m * h * h / (R - h) : 0.0;
}

/// The attraction at distance r (N, > 0 pulls the pair together) and its slope dF/dr (N/m).
struct SurfaceTensionForce {
  double force = 0.0;
  double stiffness = 0.0;
};

inline SurfaceTensionForce surface_tension_force(double r, double h, double R, double peak) {
  if (!(r > h) || !(r < R)) return {};
  const double w = std::numbers::pi / (R - h);
  const double phase = w * (r - h);
  return {peak * std::sin(phase), peak * w * std::cos(phase)};
}

/// The pair's potential U(r) (J): -F_c (L / pi) (1 + cos(pi (r - h) / L)) between h and R.
inline double surface_tension_energy(double r, double h, double R, double peak) {
  if (!(R > h) || !(r < R)) return 0.0;
  const double L = R - h;
  if (!(r > h)) return -2.0 * peak * L / std::numbers::pi;
  return -peak * (L / std::numbers::pi) * (1.0 + std::cos(std::numbers::pi * (r - h) / L));
}

}  // namespace acdr::nucleus
