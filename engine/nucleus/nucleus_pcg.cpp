// The PCG solve: filtered, block-Jacobi preconditioned conjugate gradients for the awake
// particles' velocities.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "engine/nucleus/nucleus_math.hpp"
#include "engine/nucleus/nucleus_stages.hpp"

namespace acdr::nucleus {
namespace {

// Initial guess: previous velocity with its constrained components replaced; frozen
// particles hold still (kinematic ones move at their prescribed velocity).
void warm_start(const NucleusModel& model, NucleusState& state, const StepParticles& step,
                const StepContacts& contacts, Vec3* v) {
  const std::size_t na = step.awake_end;
  for (std::size_t k = 0; k < na; ++k) v[k] = state.v[step.global[k]];
  for (std::size_t c = 0; c < contacts.particles; ++c) {
    const std::int32_t k = contacts.particle[c];
    Vec3 u = v[k];
    for (int a = 0; a < contacts.count[c]; ++a)
      u -= contacts.e[c][a] * contacts.e[c][a].dot(u);
    v[k] = u + contacts.v[c];
  }
  for (std::size_t k = na; k < step.outer_end; ++k) {
    const std::int32_t i = step.global[k];
    v[k] = state.kinematic[i] ? state.fixed_v[i] : Vec3::Zero();
  }
  for (const std::int32_t i : state.kinematic_list) state.v[i] = state.fixed_v[i];
}

}  // namespace

// Filtered, block-Jacobi preconditioned conjugate gradients on the awake particles (Baraff &
// Witkin 1998: the filter removes the constrained components), warm started from the previous
// velocities (the flow changes little between 1 ms ticks).
void solve_velocities(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work,
                      NumericalReport& report, bool resume) {
  const StepParticles& step = work.step;
  StepContacts& contacts = work.contacts;
  const StepSystem& sys = work.sys;
  PcgVectors& pcg = work.pcg;
  const std::size_t na = step.awake_end;
  Vec3* v = pcg.v.data();
  Vec3* r = pcg.r.data();
  Vec3* z = pcg.z.data();
  Vec3* p = pcg.p.data();
  Vec3* q = pcg.q.data();
  auto filter = [&](Vec3* u) {
    for (std::size_t c = 0; c < contacts.particles; ++c) {
      const std::int32_t k = contacts.particle[c];
      for (int a = 0; a < contacts.count[c]; ++a)
        u[k] -= contacts.e[c][a] * contacts.e[c][a].dot(u[k]);
    }
  };
  warm_start(model, state, step, contacts, v);
  if (!resume) {
    apply_operator(work, work.apply, v, q, step.frozen_moving);
    // A v on the constrained rows, kept along with v (A v0 + sum alpha A p): the contact
    // forces are its constrained part (reactions_and_pressure), which the filtered residual
    // drops.
    for (std::size_t c = 0; c < contacts.particles; ++c) contacts.av[c] = q[contacts.particle[c]];
    for (std::size_t k = 0; k < na; ++k) r[k] = sys.rhs[k] - q[k];
  } else {
    // The last solve's residual b - A v is whole on the rows it did not constrain (q is not
    // filtered there); on the contact rows, whose slots stay with their particles when
    // contacts let go, it is made whole from the tracked A v. The velocities are the last
    // solve's: the warm start's projection leaves them as they are (they meet every
    // constraint still held, and letting go adds none).
    for (std::size_t c = 0; c < contacts.particles; ++c) {
      const std::int32_t k = contacts.particle[c];
      r[k] = sys.rhs[k] - contacts.av[c];
    }
  }
  double b_norm2 = 0.0, g_norm2 = 0.0;
  const double g2 = model.gravity.squaredNorm();
  for (std::size_t k = 0; k < na; ++k) {
    b_norm2 += sys.rhs[k].squaredNorm();
    g_norm2 += sys.mass[k] * sys.mass[k] * g2;
  }
  filter(r);
  // Tolerance relative to the right-hand side, but never below the weight impulse scale: at
  // rest the right-hand side cancels almost exactly and a purely relative test would ask for
  // round-off.
  const double scale =
      std::sqrt(std::max(b_norm2, g_norm2 * model.solver.dt_s * model.solver.dt_s));
  const double tol = model.solver.tolerance * scale;
  double rz = 0.0;
  double r_norm = 0.0;
  for (std::size_t k = 0; k < na; ++k) z[k] = mul(sys.diag_inv[k], r[k]);
  filter(z);
  for (std::size_t k = 0; k < na; ++k) {
    p[k] = z[k];
    rz += r[k].dot(z[k]);
    r_norm += r[k].squaredNorm();
  }
  // The iterations apply only pairs with an awake particle: p is zero on the halo.
  for (std::size_t k = na; k < step.halo_end; ++k) p[k] = Vec3::Zero();
  r_norm = std::sqrt(r_norm);
  int it = 0;
  const int max_it = std::max(1, model.solver.max_iterations);
  while (r_norm > tol && it < max_it) {
    apply_operator(work, work.apply, p, q, false);
    for (std::size_t c = 0; c < contacts.particles; ++c) contacts.aq[c] = q[contacts.particle[c]];
    filter(q);
    double pq = 0.0;
    for (std::size_t k = 0; k < na; ++k) pq += p[k].dot(q[k]);
    if (!(pq > 0.0)) break;  // converged to round-off (or a non-finite value, caught later)
    const double alpha = rz / pq;
    for (std::size_t c = 0; c < contacts.particles; ++c) contacts.av[c] += alpha * contacts.aq[c];
    double rz_new = 0.0;
    double rn = 0.0;
    // r stays filtered (q is), so r . z equals r . (filtered z): the dot product is taken
    // before the filter.
    for (std::size_t k = 0; k < na; ++k) {
      v[k] += alpha * p[k];
      r[k] -= alpha * q[k];
      rn += r[k].squaredNorm();
      z[k] = mul(sys.diag_inv[k], r[k]);
      rz_new += r[k].dot(z[k]);
    }
    r_norm = std::sqrt(rn);
    ++it;
    if (r_norm <= tol) break;
    filter(z);
    const double beta = rz_new / rz;
    rz = rz_new;
    for (std::size_t k = 0; k < na; ++k) p[k] = z[k] + beta * p[k];
  }
  for (std::size_t k = 0; k < na; ++k) state.v[step.global[k]] = v[k];
  report.iterations = it;
  report.residual = scale > 0.0 ? r_norm / scale : 0.0;
  if (!std::isfinite(r_norm)) {
    report.ok = false;
    report.stage = "solve";
  }
}

}  // namespace acdr::nucleus
