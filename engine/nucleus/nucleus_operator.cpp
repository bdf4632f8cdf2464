// The operator: y = A x for the system matrix A = M + dt C + dt^2 K (+ wall terms), on the
// awake rows. x must be zero on the frozen particles unless `full`; then every pair is
// applied (needed when a frozen particle is fixed and moves, so its velocity is not zero).
// Rows of y beyond the awake particles are scratch. Pairs are walked row by row (all pairs of
// local particle i have i as their first end and a larger second end), so the first end's
// sums stay in registers.
//
// The pair part runs in single precision on 4-lane vectors (x, y, z, 0): a pair's direction
// and gradient load as one vector, its relative velocity and force are one subtraction and
// one multiplication, which halves the instructions of the double 2 + 1 lane form. The
// operator's coefficients are single precision already (PairKernel); rounding x and the sums
// perturbs A x by ~1e-7 relative, far below the solve tolerance. Mass, walls and loose bonds
// stay double.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "engine/nucleus/nucleus_stages.hpp"

namespace acdr::nucleus {
namespace {

// A pair's first 16 bytes are loaded as one vector (direction, gradient).
static_assert(offsetof(PairKernel, nx) == 0 && offsetof(PairKernel, g) == 3 * sizeof(float) &&
                  sizeof(PairKernel) >= sizeof(F4),
              "PairKernel must start with nx, ny, nz, g");

// n . d of a direction-and-gradient vector ng and a relative velocity d whose last lane is 0,
// summed as (t0 + t2) + (t1 + t3); dot3x2 gives two of them with the same sums (so a row
// gives the same bits whether its pairs go one or two at a time) in fewer shuffles.
inline float dot3(const F4& ng, const F4& d) {
  F4 t = ng * d;
  t += __builtin_shufflevector(t, t, 2, 3, 0, 1);
  t += __builtin_shufflevector(t, t, 1, 0, 3, 2);
  return t[0];
}
inline void dot3x2(const F4& ng0, const F4& d0, const F4& ng1, const F4& d1, float& dn0,
                   float& dn1) {
  const F4 t0 = ng0 * d0, t1 = ng1 * d1;
  F4 u = __builtin_shufflevector(t0, t1, 0, 1, 4, 5) + __builtin_shufflevector(t0, t1, 2, 3, 6, 7);
  u += __builtin_shufflevector(u, u, 1, 0, 3, 2);
  dn0 = u[0];
  dn1 = u[2];
}

// Pairs k and k+1 of a row: their kernels' first lanes (direction, and the gradient or 0)
// and their relative normal velocities n . (x_j - x_i).
inline void two_pairs(const PairKernel* kr, const F4* xf, std::size_t k, const F4& xi, F4& n0,
                      F4& n1, float& dn0, float& dn1) {
  std::memcpy(&n0, &kr[k], sizeof(F4));
  std::memcpy(&n1, &kr[k + 1], sizeof(F4));
  dot3x2(n0, xf[kr[k].j] - xi, n1, xf[kr[k + 1].j] - xi, dn0, dn1);
}

// Pairs k .. k+3: their kernels' first lanes and their relative normal velocities as one
// vector, each summed as dot3 sums it, (t0 + t2) + (t1 + t3), in a 4 x 4 transpose-add.
inline F4 four_pairs(const PairKernel* kr, const F4* xf, std::size_t k, const F4& xi, F4& n0,
                     F4& n1, F4& n2, F4& n3) {
  std::memcpy(&n0, &kr[k], sizeof(F4));
  std::memcpy(&n1, &kr[k + 1], sizeof(F4));
  std::memcpy(&n2, &kr[k + 2], sizeof(F4));
  std::memcpy(&n3, &kr[k + 3], sizeof(F4));
  const F4 t0 = n0 * (xf[kr[k].j] - xi), t1 = n1 * (xf[kr[k + 1].j] - xi);
  const F4 t2 = n2 * (xf[kr[k + 2].j] - xi), t3 = n3 * (xf[kr[k + 3].j] - xi);
  const F4 u01 = __builtin_shufflevector(t0, t1, 0, 1, 4, 5) +
                 __builtin_shufflevector(t0, t1, 2, 3, 6, 7);
  const F4 u23 = __builtin_shufflevector(t2, t3, 0, 1, 4, 5) +
                 __builtin_shufflevector(t2, t3, 2, 3, 6, 7);
  return F4(__builtin_shufflevector(u01, u23, 0, 2, 4, 6) +
            __builtin_shufflevector(u01, u23, 1, 3, 5, 7));
}

// Per particle, in one pass: the single-precision input, the mass and wall terms in y, and
// the wall part of the divergence (walls.slot is set on [0, halo_end)).
void load_input(const NucleusWorkspace& work, ApplyScratch& scratch, const Vec3* x, Vec3* y,
                std::size_t span, std::size_t walled) {
  F4* xf = scratch.x.data();
  F4* yf = scratch.y.data();
  float* s = scratch.s.data();
  const double* m = work.sys.mass.data();
  const std::int32_t* slot = work.walls.slot.data();
  const StepWalls& walls = work.walls;
  auto init = [&](std::size_t k) {
    xf[k] = F4{static_cast<float>(x[k].x()), static_cast<float>(x[k].y()),
               static_cast<float>(x[k].z()), 0.0f};
    yf[k] = F4{0.0f, 0.0f, 0.0f, 0.0f};
    s[k] = 0.0f;
    if (k < walled && slot[k] >= 0) {
      const std::int32_t w = slot[k];
      y[k] += walls.c[w] * x[k];
      s[k] = static_cast<float>(walls.g[w].dot(x[k]));
    }
  };
  for (std::size_t k = 0; k < work.step.awake_end; ++k) {
    y[k] = m[k] * x[k];
    init(k);
  }
  for (std::size_t k = work.step.awake_end; k < span; ++k) {
    y[k] = Vec3::Zero();
    init(k);
  }
}

// Loose bonds: dt^2 k n n^T on the relative velocity (pair bonds are in the pair term).
void apply_loose_bonds(const LooseBonds& loose, const Vec3* x, Vec3* y) {
  for (std::size_t k = 0; k < loose.count; ++k) {
    const std::int32_t i = loose.ij[2 * k], j = loose.ij[2 * k + 1];
    const Vec3& nn = loose.n[k];
    const Vec3 f = loose.a[k] * nn.dot(x[j] - x[i]) * nn;
    y[i] -= f;
    y[j] += f;
  }
}

// Near pairs [p, p_end) of a row whose first end is at xi, first pass: their divergences
// g dn scattered to the second ends (the first end's sum returned), keeping each pair's
// relative normal velocity dn.
[[gnu::always_inline]] inline float near_divergence_row(const PairKernel* kr, const F4* xf,
                                                        float* s, float* dnp, std::int32_t p,
                                                        std::int32_t p_end, const F4& xi) {
  float si = 0.0f;
  for (; p + 3 < p_end; p += 4) {
    F4 ng0, ng1, ng2, ng3;
    const F4 dn = four_pairs(kr, xf, static_cast<std::size_t>(p), xi, ng0, ng1, ng2, ng3);
    std::memcpy(&dnp[p], &dn, sizeof(F4));
    const F4 g = __builtin_shufflevector(__builtin_shufflevector(ng0, ng1, 3, 7, 3, 7),
                                         __builtin_shufflevector(ng2, ng3, 3, 7, 3, 7), 0, 1,
                                         4, 5);
    const F4 div = g * dn;
    si += div[0];
    s[kr[p].j] += div[0];
    si += div[1];
    s[kr[p + 1].j] += div[1];
    si += div[2];
    s[kr[p + 2].j] += div[2];
    si += div[3];
    s[kr[p + 3].j] += div[3];
  }
  for (; p + 1 < p_end; p += 2) {
    const PairKernel& e0 = kr[p];
    const PairKernel& e1 = kr[p + 1];
    F4 ng0, ng1;
    float dn0, dn1;
    two_pairs(kr, xf, static_cast<std::size_t>(p), xi, ng0, ng1, dn0, dn1);
    dnp[p] = dn0;
    dnp[p + 1] = dn1;
    const float div0 = e0.g * dn0, div1 = e1.g * dn1;
    si += div0;
    s[e0.j] += div0;
    si += div1;
    s[e1.j] += div1;
  }
  if (p < p_end) {
    const PairKernel& e = kr[p];
    F4 ng;
    std::memcpy(&ng, &e, sizeof(F4));
    const float dn = dot3(ng, xf[e.j] - xi);
    dnp[p] = dn;
    const float div = e.g * dn;
    si += div;
    s[e.j] += div;
  }
  return si;
}

// Far pairs [q, q_end) of a row whose first end is at xi: viscosity and pair bonds (a n n^T
// on the relative velocity), scattered to the second ends (the first end's sum returned).
[[gnu::always_inline]] inline F4 far_force_row(const PairKernel* kr, const F4* xf, F4* yf,
                                               std::size_t q, std::size_t q_end, const F4& xi) {
  F4 yi = F4{0.0f, 0.0f, 0.0f, 0.0f};
  for (; q + 3 < q_end; q += 4) {
    F4 n0, n1, n2, n3;
    const F4 dn = four_pairs(kr, xf, q, xi, n0, n1, n2, n3);
    const F4 f0 = (kr[q].a * dn[0]) * n0;
    yi -= f0;
    yf[kr[q].j] += f0;
    const F4 f1 = (kr[q + 1].a * dn[1]) * n1;
    yi -= f1;
    yf[kr[q + 1].j] += f1;
    const F4 f2 = (kr[q + 2].a * dn[2]) * n2;
    yi -= f2;
    yf[kr[q + 2].j] += f2;
    const F4 f3 = (kr[q + 3].a * dn[3]) * n3;
    yi -= f3;
    yf[kr[q + 3].j] += f3;
  }
  for (; q + 1 < q_end; q += 2) {
    const PairKernel& e0 = kr[q];
    const PairKernel& e1 = kr[q + 1];
    F4 n0, n1;
    float dn0, dn1;
    two_pairs(kr, xf, q, xi, n0, n1, dn0, dn1);
    const F4 f0 = (e0.a * dn0) * n0;
    yi -= f0;
    yf[e0.j] += f0;
    const F4 f1 = (e1.a * dn1) * n1;
    yi -= f1;
    yf[e1.j] += f1;
  }
  if (q < q_end) {
    const PairKernel& e = kr[q];
    F4 n;
    std::memcpy(&n, &e, sizeof(F4));
    const F4 f = (e.a * dot3(n, xf[e.j] - xi)) * n;
    yi -= f;
    yf[e.j] += f;
  }
  return yi;
}

// Far pairs whole, and the near pairs' first pass (the divergence of the pressure in s).
void divergence_and_far_pairs(const PairList& pairs, ApplyScratch& scratch, std::size_t rows) {
  const std::size_t cap = pairs.cap;
  const F4* xf = scratch.x.data();
  F4* yf = scratch.y.data();
  float* s = scratch.s.data();
  const PairKernel* kr = pairs.kernel.data();
  const std::int32_t* rn = pairs.row_near.data();
  const std::int32_t* rf = pairs.row_far.data();
  float* dnp = scratch.dn.data();
  for (std::size_t i = 0; i < rows; ++i) {
    const F4 xi = xf[i];
    s[i] += near_divergence_row(kr, xf, s, dnp, rn[i], rn[i + 1], xi);
    // Far pairs of row i sit at [cap - rf[i+1], cap - rf[i]); their gradient lane is 0.
    yf[i] += far_force_row(kr, xf, yf, cap - rf[i + 1], cap - rf[i], xi);
  }
}

// Near pairs, second pass: the viscous and bond force a dn n together with the gradient
// pass of the pressure, y += sum_k coef_k (grad C_k . x) grad C_k, in one scattered update.
// (The forces' last lane carries coef * g: never read.)
void near_pair_forces(const NucleusWorkspace& work, ApplyScratch& scratch, Vec3* y,
                      std::size_t rows, std::size_t span, std::size_t walled) {
  F4* yf = scratch.y.data();
  float* s = scratch.s.data();
  const float* dnp = scratch.dn.data();
  const PairKernel* kr = work.pairs.kernel.data();
  const std::int32_t* rn = work.pairs.row_near.data();
  const std::int32_t* slot = work.walls.slot.data();
  const double* pc = work.sys.press_coef.data();
  for (std::size_t k = 0; k < span; ++k) {
    s[k] = static_cast<float>(s[k] * pc[k]);
    if (k < walled && slot[k] >= 0) y[k] += static_cast<double>(s[k]) * work.walls.g[slot[k]];
  }
  for (std::size_t i = 0; i < rows; ++i) {
    const float si = s[i];
    F4 yi = F4{0.0f, 0.0f, 0.0f, 0.0f};
#pragma GCC unroll 4
    for (std::int32_t p = rn[i]; p < rn[i + 1]; ++p) {
      const PairKernel& e = kr[p];
      F4 ng;
      std::memcpy(&ng, &e, sizeof(F4));
      const F4 f = (e.a * dnp[p] + (si + s[e.j]) * e.g) * ng;
      yi -= f;
      yf[e.j] += f;
    }
    yf[i] += yi;
  }
}

}  // namespace

void apply_operator(const NucleusWorkspace& work, ApplyScratch& scratch, const Vec3* x, Vec3* y,
                    bool full) {
  const StepParticles& step = work.step;
  const std::size_t rows = full ? step.halo_end : step.awake_end;  // rows whose pairs apply
  const std::size_t span = full ? step.outer_end : step.halo_end;  // particles they reach
  const std::size_t walled = std::min(span, step.halo_end);
  load_input(work, scratch, x, y, span, walled);
  apply_loose_bonds(work.loose, x, y);
  divergence_and_far_pairs(work.pairs, scratch, rows);
  near_pair_forces(work, scratch, y, rows, span, walled);
  // The pair part, back to double.
  const F4* yf = scratch.y.data();
  for (std::size_t k = 0; k < span; ++k)
    y[k] += Vec3(static_cast<double>(yf[k][0]), static_cast<double>(yf[k][1]),
                 static_cast<double>(yf[k][2]));
}

}  // namespace acdr::nucleus
