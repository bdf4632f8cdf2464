// Registry of the built-in verification cases and the helpers they share.
#include "verification/verification_case.hpp"

#include <cassert>
#include <algorithm>
#include <cmath>

#include "verification/bone_cases.hpp"
#include "verification/cases.hpp"

namespace acdr {
namespace {

struct Kind {
  const char* name;
  VerificationCaseSpec (*defaults)(bool);
  std::vector<VerificationRow> (*run)(const VerificationCaseSpec&);
};

constexpr Kind kKinds[] = {
    {"couette_shear", verification::couette_shear_defaults, verification::run_couette_shear},
    {"buoyancy", verification::buoyancy_defaults, verification::run_buoyancy},
    {"lever_feedback", verification::lever_feedback_defaults, verification::run_lever_feedback},
    {"lift_equilibrium", verification::lift_equilibrium_defaults,
     verification::run_lift_equilibrium},
    {"bond_break", verification::bond_break_defaults, verification::run_bond_break},
    {"lump_retention", verification::lump_retention_defaults, verification::run_lump_retention},
    {"oscillator", verification::oscillator_defaults, verification::run_oscillator},
    {"viscous_decay", verification::viscous_decay_defaults, verification::run_viscous_decay},
    {"bone_compression", verification::bone_compression_defaults, verification::run_bone_compression},
    {"bone_cantilever", verification::bone_cantilever_defaults, verification::run_bone_cantilever},
    {"bone_convergence", verification::bone_convergence_defaults, verification::run_bone_convergence},
};

const Kind* find_kind(std::string_view name) {
  for (const Kind& k : kKinds)
    if (name == k.name) return &k;
  return nullptr;
}

}  // namespace

double VerificationCaseSpec::get(std::string_view param) const {
  for (const auto& p : params)
    if (p.name == param) return p.value;
  assert(false && "verification case parameter not declared by its kind");
  return std::nan("");
}

bool VerificationCaseSpec::set(std::string_view param, double value) {
  for (auto& p : params)
    if (p.name == param) {
      p.value = value;
      return true;
    }
  return false;
}

std::vector<std::string> verification_case_kinds() {
  std::vector<std::string> out;
  for (const Kind& k : kKinds) out.emplace_back(k.name);
  return out;
}

VerificationCaseSpec default_verification_case(std::string_view kind, bool fast) {
  const Kind* k = find_kind(kind);
  if (!k) return {};
  VerificationCaseSpec spec = k->defaults(fast);
  spec.kind = k->name;
  if (spec.name.empty()) spec.name = k->name;
  return spec;
}

std::vector<VerificationRow> run_verification_case(const VerificationCaseSpec& spec) {
  const Kind* k = find_kind(spec.kind);
  if (!k) {
    VerificationRow row;
    row.case_name = spec.name;
    row.quantity = "-";
    verification::fail_row(row, "unknown case kind '" + spec.kind + "'");
    return {row};
  }
  return k->run(spec);
}

std::vector<VerificationRow> run_builtin_verification(bool fast) {
  std::vector<VerificationRow> out;
  for (const Kind& k : kKinds) {
    auto rows = run_verification_case(default_verification_case(k.name, fast));
    out.insert(out.end(), rows.begin(), rows.end());
  }
  return out;
}

double relative_error(double simulated, double analytic) {
  const double diff = std::abs(simulated - analytic);
  return analytic != 0.0 ? diff / std::abs(analytic) : diff;
}

namespace verification {

void add_material_parameters(VerificationCaseSpec& spec, double dt_s) {
  const MaterialConfig m;
  spec.params.push_back({"viscosity_Pa_s", m.viscosity_Pa_s, "Pa s", "shear viscosity mu"});
  spec.params.push_back({"density_kg_m3", m.density_kg_m3, "kg/m^3", "material density rho"});
  spec.params.push_back({"bond_stiffness_N_m", m.bond_stiffness_N_m, "N/m", "bond stiffness k"});
  spec.params.push_back({"bond_break_m", m.bond_break_m, "m", "break stretch delta_max"});
  spec.params.push_back({"bulk_modulus_Pa", m.bulk_modulus_Pa, "Pa", "pressure stiffness"});
  spec.params.push_back({"spacing_m", 1.0e-3, "m", "particle spacing h"});
  spec.params.push_back({"dt_s", dt_s, "s", "time step"});
  spec.params.push_back({"gravity_m_s2", kStandardGravity, "m/s^2", "gravity magnitude (-z)"});
}

MaterialConfig material_from(const VerificationCaseSpec& spec) {
  MaterialConfig m;
  m.viscosity_Pa_s = spec.get("viscosity_Pa_s");
  m.density_kg_m3 = spec.get("density_kg_m3");
  m.bond_stiffness_N_m = spec.get("bond_stiffness_N_m");
  m.bond_break_m = spec.get("bond_break_m");
  m.bulk_modulus_Pa = spec.get("bulk_modulus_Pa");
  return m;
}

NucleusConfig nucleus_config_from(const VerificationCaseSpec& spec) {
  NucleusConfig c;
  c.enabled = true;
  c.spacing_m = spec.get("spacing_m");
  c.materials.push_back(material_from(spec));
  return c;
}

SolverConfig solver_config_from(const VerificationCaseSpec& spec) {
  SolverConfig s;
  s.dt_s = spec.get("dt_s");
  s.sleep_enabled = false;
  s.max_iterations = 400;
  s.tolerance = 1e-7;
  return s;
}

Vec3 gravity_from(const VerificationCaseSpec& spec) {
  return Vec3(0.0, 0.0, -spec.get("gravity_m_s2"));
}

void add_lattice(std::vector<Vec3>& out, const Vec3& first, int nx, int ny, int nz, double h) {
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) out.push_back(first + h * Vec3(i, j, k));
}

void step_logged(Nucleus& nucleus, double dt, std::span<const Collider> moving,
                 std::span<BodyReaction> reactions, StepLog& log) {
  NumericalReport report;
  nucleus.step(dt, moving, reactions, report);
  log.max_iterations = std::max(log.max_iterations, report.iterations);
  if (!report.ok && log.ok) {
    log.ok = false;
    log.stage = report.stage;
  }
}

VerificationRow make_row(const VerificationCaseSpec& spec, const std::string& quantity,
                         double simulated, double analytic, double tolerance) {
  VerificationRow row;
  row.case_name = spec.name;
  row.quantity = quantity;
  row.simulated = simulated;
  row.analytic = analytic;
  row.rel_error = relative_error(simulated, analytic);
  row.tolerance = tolerance;
  row.passed = std::isfinite(simulated) && row.rel_error <= tolerance;
  if (!std::isfinite(simulated)) row.note = "non-finite result";
  return row;
}

void fail_row(VerificationRow& row, const std::string& note) {
  row.passed = false;
  row.note = note;
}

}  // namespace verification
}  // namespace acdr
