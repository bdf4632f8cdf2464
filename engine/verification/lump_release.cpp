// lump_release: a lump of nucleus hanging under the prism's lower face, not bonded to it, with
// gravity pulling it away. Nothing holds material to a wall it is leaving (the no-slip coupling
// resists sliding and squeezing, not separation), so the lump falls freely: its acceleration
// once it has left the face is g, and after the fall time every particle is clear of the face.
// This is what lets a curette's cup be emptied by tipping it over the specimen tray; a wall
// term that also resisted separation would hold the lump at a creeping terminal speed.
#include <cmath>

#include "engine/verification/cases.hpp"

namespace acdr::verification {

VerificationCaseSpec lump_release_defaults(bool fast) {
  VerificationCaseSpec s;
  add_material_parameters(s, 1.0e-3);
  s.params.push_back({"lump_length_m", fast ? 4.0e-3 : 6.0e-3, "m", "lump size along x"});
  s.params.push_back({"lump_width_m", fast ? 3.0e-3 : 4.0e-3, "m", "lump size along y"});
  s.params.push_back({"lump_height_m", 2.0e-3, "m", "lump height"});
  s.params.push_back({"prism_length_m", 8.0e-3, "m", "blade length along x"});
  s.params.push_back({"prism_width_m", 6.0e-3, "m", "blade width along y"});
  s.params.push_back({"gap_fraction", 0.5, "1",
                      "top layer's distance below the face, in h (0.5 = the contact distance; "
                      "less = pressed in, as a load squeezed into a cup)"});
  s.params.push_back({"early_s", 0.01, "s", "first velocity sample (the lump has let go)"});
  s.params.push_back({"late_s", 0.05, "s", "second velocity sample"});
  s.params.push_back({"tolerance", 0.02, "1", "relative tolerance of the acceleration"});
  return s;
}

std::vector<VerificationRow> run_lump_release(const VerificationCaseSpec& spec) {
  const double h = spec.get("spacing_m");
  const double dt = spec.get("dt_s");
  const double g = spec.get("gravity_m_s2");
  const int nx = std::max(1, static_cast<int>(std::lround(spec.get("lump_length_m") / h)));
  const int ny = std::max(1, static_cast<int>(std::lround(spec.get("lump_width_m") / h)));
  const int nz = std::max(1, static_cast<int>(std::lround(spec.get("lump_height_m") / h)));
  const double face = 0.0;  // the prism's lower face at z = 0

  Collider prism;
  prism.kind = ColliderKind::kBox;
  prism.half_extents_m =
      0.5 * Vec3(spec.get("prism_length_m"), spec.get("prism_width_m"), 4.0e-3);
  prism.pose.position = Vec3(0.0, 0.0, face + prism.half_extents_m.z());
  prism.body = 0;

  // The lump: a bonded lattice block centred under the face, its top layer gap_fraction h below
  // it (0.5: the contact distance, touching, as material left in an upturned cup).
  NucleusParticleSetup setup;
  add_lattice(setup.positions_m,
              Vec3(-0.5 * (nx - 1) * h, -0.5 * (ny - 1) * h,
                   face - spec.get("gap_fraction") * h - (nz - 1) * h), nx,
              ny, nz, h);
  NucleusConfig cfg = nucleus_config_from(spec);
  {
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

  const auto mean_vz = [&nucleus] {
    double sum = 0.0;
    for (const Vec3& v : nucleus.velocities()) sum += v.z();
    return sum / static_cast<double>(nucleus.velocities().size());
  };
  BodyReaction reaction;
  StepLog log;
  const int early = std::max(1, static_cast<int>(std::lround(spec.get("early_s") / dt)));
  const int late = std::max(early + 1, static_cast<int>(std::lround(spec.get("late_s") / dt)));
  double v_early = 0.0;
  for (int s = 1; s <= late; ++s) {
    reaction.reference_point = prism.pose.position;
    step_logged(nucleus, dt, std::span<const Collider>(&prism, 1),
                std::span<BodyReaction>(&reaction, 1), log);
    if (s == early) v_early = mean_vz();
  }
  const double accel = -(mean_vz() - v_early) / ((late - early) * dt);
  // Clear of the face: beyond the reach of its wall terms (R + h/2).
  const double reach = NucleusOptions{}.neighbor_radius_factor * h + 0.5 * h;
  double released = 0.0;
  for (const Vec3& x : nucleus.positions())
    if (face - x.z() > reach) released += 1.0;
  released /= static_cast<double>(nucleus.positions().size());

  std::vector<VerificationRow> rows;
  rows.push_back(make_row(spec, "fall acceleration once released g (m/s^2)", accel, g,
                          spec.get("tolerance")));
  rows.push_back(make_row(spec, "particles clear of the face at the end (1 = all)", released, 1.0,
                          0.0));
  for (auto& row : rows)
    if (!log.ok) fail_row(row, "numerical trouble in stage " + log.stage);
  return rows;
}

}  // namespace acdr::verification
