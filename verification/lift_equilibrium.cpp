// lift_equilibrium (seed Eq. 7-8): a lump of nucleus resting on the prism's upper face while
// the prism is lifted at constant speed. With no acceleration, sum F_y = 0 (Eq. 7): the hand
// carries F = (m_stick + m_lump) g (Eq. 8). The lump's share is what the particles push on the
// prism (contact, no-slip and pressure reactions), so it is also compared on its own: it is
// the part the simulation computes, and m_stick g would otherwise hide its error.
#include <cmath>

#include "verification/cases.hpp"

namespace acdr::verification {

VerificationCaseSpec lift_equilibrium_defaults(bool fast) {
  VerificationCaseSpec s;
  add_material_parameters(s, 1.0e-3);
  s.params.push_back({"lump_length_m", fast ? 4.0e-3 : 6.0e-3, "m", "lump size along x"});
  s.params.push_back({"lump_width_m", fast ? 3.0e-3 : 4.0e-3, "m", "lump size along y"});
  s.params.push_back({"lump_height_m", fast ? 2.0e-3 : 3.0e-3, "m", "lump height"});
  s.params.push_back({"prism_length_m", 8.0e-3, "m", "blade length along x"});
  s.params.push_back({"prism_width_m", 6.0e-3, "m", "blade width along y"});
  s.params.push_back({"prism_mass_kg", 0.03, "kg", "instrument mass m_stick"});
  s.params.push_back({"lift_speed_m_s", 0.005, "m/s", "constant lifting speed"});
  s.params.push_back({"settle_s", 0.1, "s", "time at rest before lifting"});
  s.params.push_back({"lift_s", fast ? 0.1 : 0.2, "s", "lifting time (averaged: second half)"});
  s.params.push_back({"tolerance", 0.02, "1", "relative tolerance"});
  return s;
}

std::vector<VerificationRow> run_lift_equilibrium(const VerificationCaseSpec& spec) {
  const double h = spec.get("spacing_m");
  const double dt = spec.get("dt_s");
  const double g = spec.get("gravity_m_s2");
  const int nx = std::max(1, static_cast<int>(std::lround(spec.get("lump_length_m") / h)));
  const int ny = std::max(1, static_cast<int>(std::lround(spec.get("lump_width_m") / h)));
  const int nz = std::max(1, static_cast<int>(std::lround(spec.get("lump_height_m") / h)));
  const double top = 0.0;  // the prism's upper face at z = 0

  Collider prism;
  prism.kind = ColliderKind::kBox;
  prism.half_extents_m =
      0.5 * Vec3(spec.get("prism_length_m"), spec.get("prism_width_m"), 4.0e-3);
  prism.pose.position = Vec3(0.0, 0.0, top - prism.half_extents_m.z());
  prism.body = 0;

  // The lump: a bonded lattice block centred on the face, its lowest layer at h/2 above it.
  NucleusParticleSetup setup;
  add_lattice(setup.positions_m, Vec3(-0.5 * (nx - 1) * h, -0.5 * (ny - 1) * h, top + 0.5 * h),
              nx, ny, nz, h);
  NucleusConfig cfg = nucleus_config_from(spec);
  {
    // Bond lattice neighbours as the box module does (within bond_radius_factor h).
    const auto& p = setup.positions_m;
    for (std::size_t i = 0; i < p.size(); ++i)
      for (std::size_t j = i + 1; j < p.size(); ++j)
        if ((p[j] - p[i]).norm() < cfg.bond_radius_factor * h) {
          NucleusParticleSetup::Bond b;
          b.i = static_cast<int>(i);
          b.j = static_cast<int>(j);
          b.stiffness_N_m = spec.get("bond_stiffness_N_m");
          b.break_stretch_m = spec.get("bond_break_m");
          setup.bonds.push_back(b);
        }
  }
  Nucleus nucleus(cfg, solver_config_from(spec), gravity_from(spec), {}, setup, NucleusOptions{});
  const double m_lump = nucleus.masses().size() * spec.get("density_kg_m3") * h * h * h;

  BodyReaction reaction;
  StepLog log;
  const int settle = static_cast<int>(std::lround(spec.get("settle_s") / dt));
  const int lift = std::max(2, static_cast<int>(std::lround(spec.get("lift_s") / dt)));
  const double U = spec.get("lift_speed_m_s");
  double fz = 0.0;
  int count = 0;
  for (int s = 0; s < settle + lift; ++s) {
    prism.linear_velocity_m_s = Vec3(0.0, 0.0, s >= settle ? U : 0.0);
    reaction.reference_point = prism.pose.position;
    step_logged(nucleus, dt, std::span<const Collider>(&prism, 1),
                std::span<BodyReaction>(&reaction, 1), log);
    prism.pose.position += dt * prism.linear_velocity_m_s;
    if (s >= settle + lift / 2) {
      fz += reaction.force_N.z();
      ++count;
    }
  }
  fz /= count;
  const double m_stick = spec.get("prism_mass_kg");
  const double tol = spec.get("tolerance");
  std::vector<VerificationRow> rows;
  rows.push_back(make_row(spec, "lump weight on the prism m_lump g (N)", -fz, m_lump * g, tol));
  rows.push_back(make_row(spec, "hand force (m_stick + m_lump) g (N)", m_stick * g - fz,
                          (m_stick + m_lump) * g, tol));
  for (auto& row : rows)
    if (!log.ok) fail_row(row, "numerical trouble in stage " + log.stage);
  if (nucleus.broken_bond_count() > 0)
    for (auto& row : rows) row.note = "some lump bonds broke while lifting";
  return rows;
}

}  // namespace acdr::verification
