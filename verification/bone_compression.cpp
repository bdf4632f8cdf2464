// bone_compression: a block of bone under uniform compression. Rollers on three faces (x = 0,
// y = 0, z = 0 each held only normal to itself) and a uniform pressure p on the top face give
// a uniform stress sigma_zz = -p, so the top moves down by p H / E and the free sides out by
// nu p W / E. Linear tetrahedra represent a linear displacement field exactly, so the finite-
// element answer equals the closed form to round-off (relative error <= 1e-6), on any mesh.
#include <algorithm>
#include <cmath>

#include "engine/bone/boundary_surface.hpp"
#include "engine/bone/box_tet_mesh.hpp"
#include "engine/bone/elastic_model.hpp"
#include "engine/bone/surface_load.hpp"
#include "verification/bone_cases.hpp"
#include "verification/cases.hpp"

namespace acdr::verification {

VerificationCaseSpec bone_compression_defaults(bool fast) {
  VerificationCaseSpec s;
  s.params.push_back({"width_m", 10e-3, "m", "block width W (x and y)"});
  s.params.push_back({"height_m", 20e-3, "m", "block height H (z)"});
  s.params.push_back({"cells", fast ? 2.0 : 4.0, "1", "cubes across W (2x along H)"});
  s.params.push_back({"youngs_modulus_Pa", 100e6, "Pa", "E (cancellous bone)"});
  s.params.push_back({"poisson_ratio", 0.3, "1", "nu"});
  s.params.push_back({"pressure_Pa", 1e6, "Pa", "compressive pressure p on the top face"});
  s.params.push_back({"order", 1.0, "1", "element order: 1 linear, 2 quadratic tetrahedra"});
  s.params.push_back({"tolerance", 1e-6, "1", "relative tolerance"});
  return s;
}

std::vector<VerificationRow> run_bone_compression(const VerificationCaseSpec& spec) {
  const double w = spec.get("width_m"), h = spec.get("height_m"), p = spec.get("pressure_Pa");
  const int n = std::max(1, static_cast<int>(spec.get("cells")));
  const IsotropicMaterial material{spec.get("youngs_modulus_Pa"), spec.get("poisson_ratio")};
  const TetOrder order = spec.get("order") >= 1.5 ? TetOrder::kQuadratic : TetOrder::kLinear;
  const double tol = spec.get("tolerance");

  const TetMesh mesh = make_box_tet_mesh(Vec3::Zero(), Vec3(w, w, h), {n, n, 2 * n});
  std::vector<std::uint8_t> fixed(mesh.nodes.size(), 0);
  const double eps = 1e-9 * h;
  for (std::size_t i = 0; i < mesh.nodes.size(); ++i) {
    const Vec3& x = mesh.nodes[i];
    if (x.x() < eps) fixed[i] |= kFixX;
    if (x.y() < eps) fixed[i] |= kFixY;
    if (x.z() < eps) fixed[i] |= kFixZ;
  }
  const std::vector<IsotropicMaterial> materials(mesh.tets.size(), material);
  const ElasticModel model(mesh, materials, fixed, order);
  if (!model.ok()) {
    VerificationRow row = make_row(spec, "top displacement (m)", std::nan(""),
                                   -p * h / material.youngs_modulus_Pa, tol);
    fail_row(row, model.error());
    return {row};
  }
  const BoundarySurface surface(mesh);
  std::vector<double> force(model.dof_count(), 0.0), u(model.dof_count());
  for (std::size_t f = 0; f < surface.faces().size(); ++f)
    if (surface.face_normal(f).z() > 0.5)
      add_face_traction(model.space(), surface, f, Vec3(0, 0, -p), force);
  model.solve(force, u);

  // The worst node against the closed-form field u = (nu p x / E, nu p y / E, -p z / E).
  const double e = material.youngs_modulus_Pa, nu = material.poisson_ratio;
  double top = 0.0, side = 0.0, worst_field = 0.0;
  int top_count = 0, side_count = 0;
  const auto& x = model.space().nodes;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const Vec3 exact(nu * p * x[i].x() / e, nu * p * x[i].y() / e, -p * x[i].z() / e);
    const Vec3 got(u[3 * i], u[3 * i + 1], u[3 * i + 2]);
    worst_field = std::max(worst_field, (got - exact).norm() / (p * h / e));
    if (x[i].z() > h - eps) top += got.z(), ++top_count;
    if (x[i].x() > w - eps) side += got.x(), ++side_count;
  }
  std::vector<Stress6> stress(mesh.tets.size());
  model.element_stress(u, stress);
  double worst_stress = 0.0;
  for (const Stress6& s : stress) {
    Stress6 exact = Stress6::Zero();
    exact[2] = -p;
    worst_stress = std::max(worst_stress, (s - exact).cwiseAbs().maxCoeff() / p);
  }

  std::vector<VerificationRow> rows;
  rows.push_back(make_row(spec, "top displacement (m)", top / top_count, -p * h / e, tol));
  rows.push_back(make_row(spec, "side displacement (m)", side / side_count, nu * p * w / e, tol));
  VerificationRow field =
      make_row(spec, "worst nodal displacement error / (pH/E)", worst_field, 0.0, tol);
  rows.push_back(field);
  rows.push_back(make_row(spec, "worst element stress error / p", worst_stress, 0.0, tol));
  const std::string note = std::string(tet_order_name(order)) + " tetrahedra, " +
                           std::to_string(mesh.tets.size()) + " elements";
  for (auto& r : rows)
    if (r.note.empty()) r.note = note;
  return rows;
}

}  // namespace acdr::verification
