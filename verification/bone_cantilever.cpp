// bone_cantilever: a prism clamped at x = 0 (every node of that face fixed) and loaded at its
// free end by a uniform shear traction adding up to P along -z. Its tip deflection is compared
// with Timoshenko beam theory, delta = P L^3 / (3 E I) + P L / (kappa G A), with Cowper's shear
// coefficient kappa = 10 (1 + nu) / (12 + 11 nu) for a rectangle (Cowper, J Appl Mech 1966;
// 33:335). At L / h = 10 the shear term is under 1 % and the clamped face's local restraint
// of the Poisson contraction stiffens the solid by a fraction of a percent, so 2 % measures the
// elements. Bending is what linear tetrahedra do worst (shear locking: too stiff unless very
// fine); quadratic ones capture a bending field with a few elements through the depth.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/bone/boundary_surface.hpp"
#include "engine/bone/box_tet_mesh.hpp"
#include "engine/bone/elastic_model.hpp"
#include "engine/bone/surface_load.hpp"
#include "verification/bone_cases.hpp"
#include "verification/cases.hpp"

namespace acdr::verification {

VerificationCaseSpec bone_cantilever_defaults(bool fast) {
  VerificationCaseSpec s;
  s.params.push_back({"length_m", 20e-3, "m", "span L (x)"});
  s.params.push_back({"depth_m", 2e-3, "m", "depth h along the load (z)"});
  s.params.push_back({"width_m", 2e-3, "m", "width b (y)"});
  s.params.push_back({"cells_depth", 2.0, "1", "cubes across the depth and the width"});
  s.params.push_back({"cells_length", 20.0, "1", "cubes along the span"});
  s.params.push_back({"youngs_modulus_Pa", 12e9, "Pa", "E (cortical bone)"});
  s.params.push_back({"poisson_ratio", 0.3, "1", "nu"});
  s.params.push_back({"load_N", 1.0, "N", "end load P (-z)"});
  s.params.push_back({"order", 2.0, "1", "element order: 1 linear, 2 quadratic tetrahedra"});
  s.params.push_back({"tolerance", 0.02, "1", "relative tolerance"});
  (void)fast;  // the documented mesh is already small
  return s;
}

std::vector<VerificationRow> run_bone_cantilever(const VerificationCaseSpec& spec) {
  const double l = spec.get("length_m"), h = spec.get("depth_m"), b = spec.get("width_m");
  const int nd = std::max(1, static_cast<int>(spec.get("cells_depth")));
  const int nl = std::max(1, static_cast<int>(spec.get("cells_length")));
  const double e = spec.get("youngs_modulus_Pa"), nu = spec.get("poisson_ratio");
  const double load = spec.get("load_N");
  const TetOrder order = spec.get("order") >= 1.5 ? TetOrder::kQuadratic : TetOrder::kLinear;

  const double inertia = b * h * h * h / 12.0, area = b * h, shear_modulus = e / (2.0 * (1.0 + nu));
  const double kappa = 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu);
  const double bending = load * l * l * l / (3.0 * e * inertia);
  const double timoshenko = bending + load * l / (kappa * shear_modulus * area);

  const TetMesh mesh =
      make_box_tet_mesh(Vec3(0, -0.5 * b, -0.5 * h), Vec3(l, 0.5 * b, 0.5 * h), {nl, nd, nd});
  std::vector<std::uint8_t> fixed(mesh.nodes.size(), 0);
  const double eps = 1e-9 * l;
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i)
    if (mesh.nodes[i].x() < eps) fixed[i] = kFixAll;
  const std::vector<IsotropicMaterial> materials(mesh.tets.size(), IsotropicMaterial{e, nu});
  const ElasticModel model(mesh, materials, fixed, order);
  VerificationRow row;
  if (!model.ok()) {
    row = make_row(spec, "tip deflection (m)", std::nan(""), timoshenko, spec.get("tolerance"));
    fail_row(row, model.error());
    return {row};
  }
  const BoundarySurface surface(mesh);
  std::vector<double> force(model.dof_count(), 0.0), u(model.dof_count());
  for (std::size_t f = 0; f < surface.faces().size(); ++f)
    if (surface.face_normal(f).x() > 0.5)
      add_face_traction(model.space(), surface, f, Vec3(0, 0, -load / area), force);
  model.solve(force, u);

  // Mean vertical displacement of the end face's nodes.
  double tip = 0.0;
  int count = 0;
  const auto& x = model.space().nodes;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (x[i].x() > l - eps) tip += -u[3 * i + 2], ++count;
  row = make_row(spec, "tip deflection (m)", tip / count, timoshenko, spec.get("tolerance"));
  char note[160];
  std::snprintf(note, sizeof note, "%s tetrahedra, %zu elements, %zu dofs; Euler-Bernoulli %.4g m",
                tet_order_name(order), mesh.tets.size(), model.report().free_dofs, bending);
  if (row.note.empty()) row.note = note;
  return {row};
}

}  // namespace acdr::verification
