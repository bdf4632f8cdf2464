// viscous_decay: a shear wave u_x = U sin(2 pi y / L) in a fully periodic box of the fluid
// (bonds off, gravity off) decays as exp(-nu k^2 t), nu = mu / rho, k = 2 pi / L (the
// diffusion equation that the Navier-Stokes equations reduce to for this divergence-free,
// unidirectional flow). The decay rate is fitted (least squares on log amplitude) and
// compared with nu k^2. The rate is fast (1/(nu k^2) ~ 27 us for mu = 250 Pa s, L = 16 mm), so
// the default step is 0.5 us; backward Euler underestimates the rate by ~ nu k^2 dt / 2 and
// the lattice by (k h)^2 / 12.
#include <cmath>
#include <numbers>

#include "verification/cases.hpp"

namespace acdr::verification {

VerificationCaseSpec viscous_decay_defaults(bool fast) {
  VerificationCaseSpec s;
  add_material_parameters(s, 0.5e-6);
  s.set("gravity_m_s2", 0.0);
  s.params.push_back({"wavelength_m", fast ? 16.0e-3 : 24.0e-3, "m", "wave length L (periodic)"});
  s.params.push_back({"amplitude_m_s", 1.0e-3, "m/s", "initial amplitude U"});
  s.params.push_back({"decay_fraction", 0.5, "1", "simulate until the amplitude is this fraction"});
  s.params.push_back({"tolerance", 0.05, "1", "relative tolerance"});
  return s;
}

std::vector<VerificationRow> run_viscous_decay(const VerificationCaseSpec& spec) {
  const double h = spec.get("spacing_m");
  const double dt = spec.get("dt_s");
  const double nu = spec.get("viscosity_Pa_s") / spec.get("density_kg_m3");
  const int ny = std::max(4, static_cast<int>(std::lround(spec.get("wavelength_m") / h)));
  const int nx = 4, nz = 4;
  const double L = ny * h;
  const double k = 2.0 * std::numbers::pi / L;
  const double rate = nu * k * k;
  const double U = spec.get("amplitude_m_s");

  NucleusParticleSetup setup;
  add_lattice(setup.positions_m, Vec3(0.5 * h, 0.5 * h, 0.5 * h), nx, ny, nz, h);
  for (const Vec3& p : setup.positions_m)
    setup.velocities_m_s.push_back(Vec3(U * std::sin(k * p.y()), 0.0, 0.0));
  NucleusOptions opt;
  opt.bonds_enabled = false;
  opt.periodic = {true, true, true};
  opt.periodic_min_m = Vec3::Zero();
  opt.periodic_max_m = Vec3(nx * h, L, nz * h);
  Nucleus nucleus(nucleus_config_from(spec), solver_config_from(spec), gravity_from(spec), {},
                  setup, opt);

  // Mode amplitude a(t) = 2/N sum u_x sin(k y); least-squares slope of log a against t.
  auto amplitude = [&] {
    double a = 0.0;
    const auto x = nucleus.positions();
    const auto v = nucleus.velocities();
    for (std::size_t i = 0; i < x.size(); ++i) a += v[i].x() * std::sin(k * x[i].y());
    return 2.0 * a / x.size();
  };
  const double t_end = std::log(1.0 / std::clamp(spec.get("decay_fraction"), 1e-6, 0.99)) / rate;
  const int steps = std::max(5, static_cast<int>(std::ceil(t_end / dt)));
  StepLog log;
  double st = 0, sl = 0, stt = 0, stl = 0;
  int n = 0;
  for (int s = 1; s <= steps; ++s) {
    step_logged(nucleus, dt, {}, {}, log);
    const double a = amplitude();
    if (!(a > 0.0)) break;
    const double t = s * dt, l = std::log(a);
    st += t;
    sl += l;
    stt += t * t;
    stl += t * l;
    ++n;
  }
  const double slope = n >= 2 ? (n * stl - st * sl) / (n * stt - st * st) : std::nan("");
  VerificationRow row =
      make_row(spec, "decay rate nu k^2 (1/s)", -slope, rate, spec.get("tolerance"));
  if (!log.ok) fail_row(row, "numerical trouble in stage " + log.stage);
  return {row};
}

}  // namespace acdr::verification
