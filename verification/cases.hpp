// Internal to verification/: the built-in cases (one file each) and the scene helpers
// they share.
#pragma once

#include <span>
#include <vector>

#include "engine/nucleus/nucleus.hpp"
#include "verification/verification_case.hpp"

namespace acdr::verification {

// Each case: its default parameters and its runner.
VerificationCaseSpec couette_shear_defaults(bool fast);
std::vector<VerificationRow> run_couette_shear(const VerificationCaseSpec& spec);
VerificationCaseSpec buoyancy_defaults(bool fast);
std::vector<VerificationRow> run_buoyancy(const VerificationCaseSpec& spec);
VerificationCaseSpec lever_feedback_defaults(bool fast);
std::vector<VerificationRow> run_lever_feedback(const VerificationCaseSpec& spec);
VerificationCaseSpec lift_equilibrium_defaults(bool fast);
std::vector<VerificationRow> run_lift_equilibrium(const VerificationCaseSpec& spec);
VerificationCaseSpec bond_break_defaults(bool fast);
std::vector<VerificationRow> run_bond_break(const VerificationCaseSpec& spec);
VerificationCaseSpec lump_retention_defaults(bool fast);
std::vector<VerificationRow> run_lump_retention(const VerificationCaseSpec& spec);
VerificationCaseSpec oscillator_defaults(bool fast);
std::vector<VerificationRow> run_oscillator(const VerificationCaseSpec& spec);
VerificationCaseSpec viscous_decay_defaults(bool fast);
std::vector<VerificationRow> run_viscous_decay(const VerificationCaseSpec& spec);

/// Parameters every case shares: material, spacing, step, gravity magnitude.
void add_material_parameters(VerificationCaseSpec& spec, double dt_s);

/// Material, nucleus config and solver config from the shared parameters (sleep off: the
/// cases measure the solver itself).
MaterialConfig material_from(const VerificationCaseSpec& spec);
NucleusConfig nucleus_config_from(const VerificationCaseSpec& spec);
SolverConfig solver_config_from(const VerificationCaseSpec& spec);
Vec3 gravity_from(const VerificationCaseSpec& spec);

/// Cubic lattice of nx*ny*nz points with spacing h, first point at `first`.
void add_lattice(std::vector<Vec3>& out, const Vec3& first, int nx, int ny, int nz, double h);

/// Steps a nucleus, accumulating the first numerical failure.
struct StepLog {
  bool ok = true;
  std::string stage;
  int max_iterations = 0;
};
void step_logged(Nucleus& nucleus, double dt, std::span<const Collider> moving,
                 std::span<BodyReaction> reactions, StepLog& log);

/// A compared row with the relative error and pass flag filled in.
VerificationRow make_row(const VerificationCaseSpec& spec, const std::string& quantity,
                         double simulated, double analytic, double tolerance);

/// Marks a row failed with a note (NaN, solver trouble).
void fail_row(VerificationRow& row, const std::string& note);

}  // namespace acdr::verification
