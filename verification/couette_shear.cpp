// couette_shear (seed Eq. 1-3): a plate of area A dragged at speed U over a nucleus layer of
// thickness H on a fixed floor. In steady plane Couette flow the shear stress is uniform,
// tau = mu U / H, so the plate feels F = mu A U / H. The layer is periodic in x and y, so the
// plate is effectively infinite (no edge flow) and A is the periodic cell's area. The material
// is the viscous fluid (bonds off): with bonds the layer would be a solid until they tear.
#include <cmath>

#include "verification/cases.hpp"

namespace acdr::verification {

VerificationCaseSpec couette_shear_defaults(bool fast) {
  VerificationCaseSpec s;
  add_material_parameters(s, 1.0e-3);
  s.params.push_back({"gap_m", 4.0e-3, "m", "layer thickness H (floor to plate)"});
  s.params.push_back({"plate_length_m", fast ? 6.0e-3 : 10.0e-3, "m", "plate length along U"});
  s.params.push_back({"plate_width_m", fast ? 6.0e-3 : 8.0e-3, "m", "plate width"});
  s.params.push_back({"plate_speed_m_s", 0.01, "m/s", "plate speed U"});
  s.params.push_back({"duration_s", fast ? 0.01 : 0.03, "s", "simulated time"});
  s.params.push_back({"tolerance", 0.05, "1", "relative tolerance"});
  return s;
}

std::vector<VerificationRow> run_couette_shear(const VerificationCaseSpec& spec) {
  const double h = spec.get("spacing_m");
  const double mu = spec.get("viscosity_Pa_s");
  const double U = spec.get("plate_speed_m_s");
  const double dt = spec.get("dt_s");
  // The domain holds whole lattice cells; A and H are those of the simulated domain.
  const int nx = std::max(2, static_cast<int>(std::lround(spec.get("plate_length_m") / h)));
  const int ny = std::max(2, static_cast<int>(std::lround(spec.get("plate_width_m") / h)));
  const int nz = std::max(1, static_cast<int>(std::lround(spec.get("gap_m") / h)));
  const double Lx = nx * h, Ly = ny * h, H = nz * h;

  NucleusParticleSetup setup;
  add_lattice(setup.positions_m, Vec3(0.5 * h, 0.5 * h, 0.5 * h), nx, ny, nz, h);
  NucleusOptions opt;
  opt.bonds_enabled = false;
  opt.periodic = {true, true, false};
  opt.periodic_min_m = Vec3::Zero();
  opt.periodic_max_m = Vec3(Lx, Ly, 0.0);

  Collider floor;
  floor.kind = ColliderKind::kHalfSpace;
  Collider plate;
  plate.kind = ColliderKind::kBox;
  plate.half_extents_m = Vec3(10.0 * Lx, 10.0 * Ly, h);
  plate.pose.position = Vec3(0.5 * Lx, 0.5 * Ly, H + h);
  plate.linear_velocity_m_s = Vec3(U, 0.0, 0.0);
  plate.body = 0;

  Nucleus nucleus(nucleus_config_from(spec), solver_config_from(spec), gravity_from(spec),
                  std::span<const Collider>(&floor, 1), setup, opt);
  const int steps = std::max(4, static_cast<int>(std::lround(spec.get("duration_s") / dt)));
  BodyReaction reaction;
  double sum = 0.0;
  int count = 0;
  bool ok = true;
  std::string stage;
  for (int s = 0; s < steps; ++s) {
    NumericalReport report;
    nucleus.step(dt, std::span<const Collider>(&plate, 1), std::span<BodyReaction>(&reaction, 1),
                 report);
    if (!report.ok && ok) {
      ok = false;
      stage = report.stage;
    }
    // The plate is translation invariant along x: keep it in place (its velocity is what
    // matters). Average the second half of the run (steady state).
    if (s >= steps / 2) {
      sum += -reaction.force_N.x();
      ++count;
    }
  }
  const double simulated = sum / count;
  const double analytic = mu * Lx * Ly * U / H;
  VerificationRow row =
      make_row(spec, "plate shear force F (N)", simulated, analytic, spec.get("tolerance"));
  if (!ok) fail_row(row, std::string("numerical trouble in stage ") + stage);
  return {row};
}

}  // namespace acdr::verification
