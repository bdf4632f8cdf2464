// System assembly: per-step coefficients, right-hand side and block-Jacobi preconditioner of
// (M + dt C + dt^2 K) v1 = M v0 + dt f0 (see nucleus.cpp), and the solver's compact pair
// records. Rows of the system are needed for the awake particles only; pairs without an
// awake particle enter only the densities and second moments (of the halo). Three passes over
// the pairs: neighbour sums; then, per pair with an awake particle, its coefficient, its
// forces on the right-hand side, its share of the diagonal blocks and the solver's record.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include <emmintrin.h>

#include "engine/nucleus/nucleus_math.hpp"
#include "engine/nucleus/nucleus_stages.hpp"
#include "engine/nucleus/surface_tension.hpp"

namespace acdr::nucleus {
namespace {

// Pairs [begin, end): the viscous weight from the length, two at a time (its two square
// roots would otherwise wait on each other inside the summing loops below; the same correctly
// rounded operations, so the same bits).
void viscous_weights(PairList& pairs, std::size_t begin, std::size_t end, double inv_R) {
  const double* r = pairs.r.data();
  double* wv = pairs.wv.data();
  const __m128d one = _mm_set1_pd(1.0), zero = _mm_setzero_pd(), s = _mm_set1_pd(inv_R);
  std::size_t p = begin;
  for (; p + 1 < end; p += 2) {
    // max(x, 0) as std::max(0.0, x) takes it: x when 0 < x, else 0.
    const __m128d q = _mm_max_pd(_mm_sub_pd(one, _mm_mul_pd(_mm_loadu_pd(r + p), s)), zero);
    _mm_storeu_pd(wv + p, _mm_mul_pd(q, _mm_sqrt_pd(_mm_sqrt_pd(q))));
  }
  if (p < end) wv[p] = viscous_weight_of(std::max(0.0, 1.0 - r[p] * inv_R));
}

// Neighbour sums: density (kernel units) and second moment, the kernels' q from the
// reciprocal radii (every near pair is inside both radii); each near pair's density gradient
// g and each pair's viscous weight.
void neighbour_sums(const NucleusModel& model, const StepParticles& step, PairList& pairs,
                    StepSystem& sys) {
  const double R = model.radius;
  const double Rd = model.density_radius;
  const std::size_t cap = pairs.cap;
  for (std::size_t k = step.halo_end; k < step.outer_end; ++k) {
    sys.density[k] = 0.0;  // outer particles: partial sums, never read
    sys.second_moment[k] = 0.0;
  }
  const double inv_R = 1.0 / R, inv_Rd = 1.0 / Rd;
  const double slope_scale = -3.0 * inv_Rd / model.n0;  // dw/dr / n0 = slope_scale q^2
  viscous_weights(pairs, 0, pairs.near, inv_R);
  viscous_weights(pairs, cap - pairs.far, cap, inv_R);
  const double* pw = pairs.wv.data();
  // Row by row (every pair of row k has k as its first end), the first end's sums in
  // registers.
  const std::int32_t* pj = pairs.j.data();
  const double* pr = pairs.r.data();
  for (std::size_t k = 0; k < step.halo_end; ++k) {
    double dk = 1.0;  // self
    double mk = 0.0;
    for (std::int32_t p = pairs.row_near[k]; p < pairs.row_near[k + 1]; ++p) {
      const std::int32_t j = pj[p];
      const double r = pr[p];
      const double qd = std::max(0.0, 1.0 - r * inv_Rd);
      const double w = kernel_of(qd);
      const double m2 = pw[p] * r * r;
      dk += w;
      sys.density[j] += w;
      pairs.g[p] = slope_scale * qd * qd;
      mk += m2;
      sys.second_moment[j] += m2;
    }
    for (std::size_t p = cap - pairs.row_far[k + 1]; p < cap - pairs.row_far[k]; ++p) {
      const std::int32_t j = pj[p];
      const double r = pr[p];
      const double m2 = pw[p] * r * r;
      mk += m2;
      sys.second_moment[j] += m2;
    }
    sys.density[k] += dk;
    sys.second_moment[k] += mk;
  }
}

// Per particle. Viscous coefficients c_ij = w_ij 2 mu V / T, with T the weighted fourth
// moment sum w r_x^2 r_z^2 / r^2 of the neighbourhood: the stress of the pair operator under
// a shear rate gamma is gamma T c / (2 V w), so this gives tau = mu gamma (see the file
// comment of nucleus.cpp). T is the rest lattice's t0 scaled by the particle's own weighted
// second moment S / s0 (for isotropic directions T = S / 15), so a disordered or compressed
// neighbourhood is normalised by what it actually holds. S is floored at 0.6 s0 so a sparse
// neighbourhood (free surface, loose particles) does not get an unbounded coefficient.
// Pressure constraint C_i and which particles carry it (compression only, with a 1 % margin
// so a particle about to be compressed is already implicit).
void particle_coefficients(const NucleusModel& model, const StepParticles& step,
                           StepSystem& sys, double dt) {
  for (std::size_t k = 0; k < step.halo_end; ++k) {
    const std::int32_t i = step.global[k];
    sys.visc_coef[k] = 2.0 * model.mu[i] * model.volume * model.s0 /
                       (model.t0 * std::max(sys.second_moment[k], 0.6 * model.s0));
    sys.constraint[k] = sys.density[k] / model.n0 - 1.0;
    sys.press_coef[k] = sys.constraint[k] > -0.01 ? dt * dt * model.kappa[i] * model.volume : 0.0;
  }
  for (std::size_t k = step.halo_end; k < step.outer_end; ++k) {
    sys.constraint[k] = 0.0;
    sys.press_coef[k] = 0.0;
    sys.visc_coef[k] = 0.0;
  }
}

// Right-hand side: forces at the start of the step (as dt * f) and M v0; rows beyond the
// awake particles are scratch. Walls: the no-slip tensor, the wall pressure, the no-slip
// drag toward a moving wall, and the density change the wall's own motion causes
// (s_i = press_coef * sum_w grad . v_w in sys.div, scattered through grad C in pair_terms).
void right_hand_side(const NucleusModel& model, const NucleusState& state,
                     const StepParticles& step, StepWalls& walls, StepSystem& sys, double dt) {
  for (std::size_t k = 0; k < step.outer_end; ++k) {
    const std::int32_t i = step.global[k];
    sys.rhs[k] = dt * (model.mass[i] * model.gravity + state.f_ext[i]);
  }
  for (std::size_t k = 0; k < step.awake_end; ++k) {
    sys.mass[k] = model.mass[step.global[k]];
    sys.rhs[k] += sys.mass[k] * state.v[step.global[k]];
  }
  for (std::size_t k = 0; k < step.halo_end; ++k) sys.div[k] = 0.0;
  for (std::size_t w = 0; w < walls.hit_count; ++w) {
    const WallHit& hit = walls.hits[w];
    const std::int32_t k = hit.particle;
    walls.c[walls.slot[k]] += (dt * sys.visc_coef[k]) * hit.visc;
    sys.rhs[k] += (dt * sys.visc_coef[k]) * (hit.visc * hit.v_wall);
    sys.div[k] += hit.grad.dot(hit.v_wall);
  }
  for (std::size_t k = 0; k < step.halo_end; ++k) sys.div[k] *= sys.press_coef[k];
  for (std::size_t w = 0; w < walls.particles; ++w) {
    const std::int32_t k = walls.particle[w];
    sys.rhs[k] -= dt * model.kappa[step.global[k]] * model.volume *
                  std::max(sys.constraint[k], 0.0) * walls.g[w];
    sys.rhs[k] += sys.div[k] * walls.g[w];
  }
}

// Block-Jacobi preconditioner, first part: the 3x3 diagonal blocks of the system matrix
// (awake rows) start from the mass and the walls' no-slip tensors; grad_i C_i = -sum_j g_ij
// n_ij + wall_g_i starts from the wall part, accumulated in pcg.q as scratch.
void diagonal_from_mass_and_walls(const StepParticles& step, const StepWalls& walls,
                                  StepSystem& sys, PcgVectors& pcg) {
  for (std::size_t k = 0; k < step.halo_end; ++k) {
    const double m = k < step.awake_end ? sys.mass[k] : 1.0;
    sys.diag_inv[k] = {m, m, m, 0.0, 0.0, 0.0};
    pcg.q[k] = Vec3::Zero();
  }
  for (std::size_t w = 0; w < walls.particles; ++w) {
    const std::int32_t k = walls.particle[w];
    const Eigen::Matrix3d& C = walls.c[w];
    Sym3& d = sys.diag_inv[k];
    d[0] += C(0, 0);
    d[1] += C(1, 1);
    d[2] += C(2, 2);
    d[3] += 0.5 * (C(0, 1) + C(1, 0));
    d[4] += 0.5 * (C(0, 2) + C(2, 0));
    d[5] += 0.5 * (C(1, 2) + C(2, 1));
    pcg.q[k] = walls.g[w];
  }
}

// Pairs with an awake particle: the implicit coefficient dt c_ij (+ dt^2 k of its bond),
// the bond force k (r - L) along the pair, the pressure force, the wall-motion term, the
// diagonal blocks, and the solver's record. The solver's copy is single precision: the
// iterations stream it, so its size sets their speed; rounding perturbs the operator by
// ~1e-7 relative (far below the solve tolerance) and symmetrically (both ends of a pair read
// the same record), so it stays symmetric positive definite.
void pair_terms(const NucleusModel& model, const ReformedBonds& reformed,
                const StepParticles& step, PairList& pairs, StepSystem& sys, PcgVectors& pcg,
                double dt) {
  const std::size_t cap = pairs.cap;
  // Per particle of the step: the pressure force factor dt kappa V max(C, 0) and half the
  // viscous coefficient times dt (zero beyond the halo).
  double* pf = sys.press_force.data();
  double* hv = sys.half_visc.data();
  for (std::size_t k = 0; k < step.outer_end; ++k) {
    pf[k] = dt * model.kappa[step.global[k]] * model.volume * std::max(sys.constraint[k], 0.0);
    hv[k] = 0.5 * dt * sys.visc_coef[k];
  }
  const double* pc = sys.press_coef.data();
  const double dt2 = dt * dt;
  // Row by row over the awake particles (their rows hold exactly the pairs with an awake
  // particle), the first end's sums in registers.
  for (std::size_t k = 0; k < step.halo_end; ++k) pf[k] -= sys.div[k];  // less wall motion
  // The arrays as local pointers: the scattered stores below could alias the vectors' own
  // members, so the compiler would otherwise reload every base pointer for every pair.
  const std::int32_t* pj = pairs.j.data();
  const double* pr = pairs.r.data();
  const Vec3* pn = pairs.n.data();
  const double* pa = pairs.wv.data();
  const double* pg = pairs.g.data();
  const std::int32_t* pb = pairs.bond.data();
  // Bond b's stiffness and rest length: built bonds [0, B), then the re-formed ones.
  const std::int32_t nb = static_cast<std::int32_t>(model.bonds.size());
  const double* bk = model.bonds.k.data();
  const double* brest = model.bonds.rest.data();
  const double* rk = reformed.k.data();
  const double* rrest = reformed.rest.data();
  Vec3* rhs = sys.rhs.data();
  Vec3* qv = pcg.q.data();
  Sym3* diag = sys.diag_inv.data();
  PairKernel* kern = pairs.kernel.data();
  const std::int32_t* rnear = pairs.row_near.data();
  const std::int32_t* rfar = pairs.row_far.data();
  // Surface tension between pieces of one material that no built bond joins (none, or a
  // re-formed one): its rising part implicit, like a bond's (surface_tension.hpp).
  const std::int32_t* global = step.global.data();
  const double* tension = model.tension_force.data();
  const std::uint8_t* material = model.material.data();
  const double h = model.h, R = model.tension_reach;
  for (std::size_t i = 0; i < step.awake_end; ++i) {
    const double hv_i = hv[i], pf_i = pf[i], pc_i = pc[i];
    const double tension_i = model.surface_tension ? tension[global[i]] : 0.0;
    const std::uint8_t material_i = material[global[i]];
    Vec3 rhs_i = Vec3::Zero();
    Vec3 q_i = Vec3::Zero();
    double d0 = 0.0, d1 = 0.0, d2 = 0.0, d3 = 0.0, d4 = 0.0, d5 = 0.0;
    for (std::int32_t p = rnear[i]; p < rnear[i + 1]; ++p) {
      const std::int32_t j = pj[p];
      const Vec3& nn = pn[p];
      double a = pa[p] * (hv_i + hv[j]);
      const double g = pg[p];
      double fs = (pf_i + pf[j]) * g;
      const std::int32_t b = pb[p];
      if (b >= 0) {
        const double k = b < nb ? bk[b] : rk[b - nb];
        a += dt2 * k;
        fs += dt * k * (pr[p] - (b < nb ? brest[b] : rrest[b - nb]));
      }
      if (tension_i > 0.0 && (b < 0 || b >= nb) && material[global[j]] == material_i) {
        const SurfaceTensionForce t = surface_tension_force(pr[p], h, R, tension_i);
        a += dt2 * std::max(t.stiffness, 0.0);
        fs += dt * t.force;
      }
      const Vec3 f = fs * nn;
      rhs_i += f;
      rhs[j] -= f;
      const double g2 = g * g;
      const double ai = a + pc[j] * g2, aj = a + pc_i * g2;
      const double xx = nn.x() * nn.x(), yy = nn.y() * nn.y(), zz = nn.z() * nn.z();
      const double xy = nn.x() * nn.y(), xz = nn.x() * nn.z(), yz = nn.y() * nn.z();
      d0 += ai * xx; d1 += ai * yy; d2 += ai * zz; d3 += ai * xy; d4 += ai * xz; d5 += ai * yz;
      Sym3& dj = diag[j];
      dj[0] += aj * xx; dj[1] += aj * yy; dj[2] += aj * zz;
      dj[3] += aj * xy; dj[4] += aj * xz; dj[5] += aj * yz;
      q_i -= g * nn;
      qv[j] += g * nn;
      kern[p] = {static_cast<float>(nn.x()), static_cast<float>(nn.y()),
                 static_cast<float>(nn.z()), static_cast<float>(g), j, static_cast<float>(a)};
    }
    for (std::size_t p = cap - rfar[i + 1]; p < cap - rfar[i]; ++p) {
      const std::int32_t j = pj[p];
      const Vec3& nn = pn[p];
      double a = pa[p] * (hv_i + hv[j]);
      const std::int32_t b = pb[p];
      if (b >= 0) {
        const double k = b < nb ? bk[b] : rk[b - nb];
        a += dt2 * k;
        const Vec3 f = (dt * k * (pr[p] - (b < nb ? brest[b] : rrest[b - nb]))) * nn;
        rhs_i += f;
        rhs[j] -= f;
      }
      if (tension_i > 0.0 && (b < 0 || b >= nb) && material[global[j]] == material_i) {
        const SurfaceTensionForce t = surface_tension_force(pr[p], h, R, tension_i);
        a += dt2 * std::max(t.stiffness, 0.0);
        const Vec3 f = (dt * t.force) * nn;
        rhs_i += f;
        rhs[j] -= f;
      }
      const double xx = nn.x() * nn.x(), yy = nn.y() * nn.y(), zz = nn.z() * nn.z();
      const double xy = nn.x() * nn.y(), xz = nn.x() * nn.z(), yz = nn.y() * nn.z();
      d0 += a * xx; d1 += a * yy; d2 += a * zz; d3 += a * xy; d4 += a * xz; d5 += a * yz;
      Sym3& dj = diag[j];
      dj[0] += a * xx; dj[1] += a * yy; dj[2] += a * zz;
      dj[3] += a * xy; dj[4] += a * xz; dj[5] += a * yz;
      kern[p] = {static_cast<float>(nn.x()), static_cast<float>(nn.y()),
                 static_cast<float>(nn.z()), 0.0f, j, static_cast<float>(a)};
    }
    rhs[i] += rhs_i;
    qv[i] += q_i;
    Sym3& di = diag[i];
    di[0] += d0; di[1] += d1; di[2] += d2; di[3] += d3; di[4] += d4; di[5] += d5;
  }
}

// Pairs without an awake particle never act on an awake row (coefficient 0); their density
// gradient still matters when a frozen particle moves (a full apply, the only reader).
void kernels_of_idle_pairs(const StepParticles& step, PairList& pairs) {
  if (!step.frozen_moving) return;
  for (std::size_t p = pairs.near_awake; p < pairs.near; ++p)
    pairs.kernel[p] = {static_cast<float>(pairs.n[p].x()), static_cast<float>(pairs.n[p].y()),
                       static_cast<float>(pairs.n[p].z()), static_cast<float>(pairs.g[p]),
                       pairs.j[p], 0.0f};
  for (std::size_t p = pairs.cap - pairs.far; p < pairs.cap - pairs.far_awake; ++p)
    pairs.kernel[p] = {0.0f, 0.0f, 0.0f, 0.0f, pairs.j[p], 0.0f};
}

// Loose bonds cache their direction and implicit coefficient dt^2 k for the solver, and add
// their force and diagonal share.
void loose_bond_terms(const NucleusModel& model, const NucleusState& state,
                      const StepParticles& step, LooseBonds& loose, StepSystem& sys,
                      double dt) {
  for (std::size_t k = 0; k < loose.count; ++k) {
    const std::int32_t b = loose.bond[k];
    loose.a[k] = 0.0;
    const std::int32_t li = loose.ij[2 * k], lj = loose.ij[2 * k + 1];
    const Vec3 d = min_image(model, state.x[step.global[lj]] - state.x[step.global[li]]);
    const double r = d.norm();
    if (r <= 0.0) continue;
    loose.n[k] = d / r;
    loose.a[k] = dt * dt * model.bonds.k[b];
    const Vec3 f = dt * model.bonds.k[b] * (r - model.bonds.rest[b]) * loose.n[k];
    sys.rhs[li] += f;
    sys.rhs[lj] -= f;
    add_outer(sys.diag_inv[li], loose.a[k], loose.n[k]);
    add_outer(sys.diag_inv[lj], loose.a[k], loose.n[k]);
  }
}

// The pressure's diagonal share press_coef grad C grad C^T, then the blocks inverted.
void invert_diagonal(const StepParticles& step, StepSystem& sys, const PcgVectors& pcg) {
  for (std::size_t k = 0; k < step.awake_end; ++k) {
    add_outer(sys.diag_inv[k], sys.press_coef[k], pcg.q[k]);
    sys.diag_inv[k] = inverse(sys.diag_inv[k]);
  }
}

}  // namespace

void assemble(const NucleusModel& model, const NucleusState& state, NucleusWorkspace& work,
              double dt) {
  neighbour_sums(model, work.step, work.pairs, work.sys);
  particle_coefficients(model, work.step, work.sys, dt);
  right_hand_side(model, state, work.step, work.walls, work.sys, dt);
  diagonal_from_mass_and_walls(work.step, work.walls, work.sys, work.pcg);
  pair_terms(model, state.reformed, work.step, work.pairs, work.sys, work.pcg, dt);
  kernels_of_idle_pairs(work.step, work.pairs);
  loose_bond_terms(model, state, work.step, work.loose, work.sys, dt);
  invert_diagonal(work.step, work.sys, work.pcg);
}

}  // namespace acdr::nucleus
