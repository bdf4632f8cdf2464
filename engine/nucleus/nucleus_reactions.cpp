// Reactions and pressure: what the particles do to the moving bodies, from the solved
// velocities (so the forces are the end-of-step implicit ones the particles felt): contact
// constraint forces, no-slip drag and the wall part of the pressure. Also the particle
// pressures for output.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "engine/nucleus/nucleus_stages.hpp"

namespace acdr::nucleus {
namespace {

// Divergence of the solved velocity (relative to moving walls): C at the end of the step is
// C + dt * s, and the pressure kappa * that.
void end_of_step_pressures(const NucleusModel& model, NucleusState& state,
                           NucleusWorkspace& work, double dt) {
  const StepParticles& step = work.step;
  const StepWalls& walls = work.walls;
  const PairList& pairs = work.pairs;
  StepSystem& sys = work.sys;
  const Vec3* v = work.pcg.v.data();
  const std::size_t rows = step.frozen_moving ? step.outer_end : step.halo_end;
  for (std::size_t k = 0; k < rows; ++k) sys.div[k] = 0.0;
  for (std::size_t w = 0; w < walls.particles; ++w) {
    const std::int32_t k = walls.particle[w];
    sys.div[k] = walls.g[w].dot(v[k]);
  }
  for (std::size_t w = 0; w < walls.hit_count; ++w) {
    const WallHit& hit = walls.hits[w];
    sys.div[hit.particle] -= hit.grad.dot(hit.v_wall);
  }
  // Row by row (the near pairs [0, near_awake) or [0, near) are rows [0, awake_end) or [0,
  // halo_end)), the first end's sum in a register: it is complete from the earlier rows when
  // its own row starts, and no later row reaches it, so the additions are the same in the
  // same order.
  const std::size_t near_rows = step.frozen_moving ? step.halo_end : step.awake_end;
  const std::int32_t* rn = pairs.row_near.data();
  const std::int32_t* pj = pairs.j.data();
  const double* pg = pairs.g.data();
  const Vec3* pn = pairs.n.data();
  double* s = sys.div.data();
  for (std::size_t i = 0; i < near_rows; ++i) {
    const Vec3 vi = v[i];
    double si = s[i];
    for (std::int32_t p = rn[i]; p < rn[i + 1]; ++p) {
      const std::int32_t j = pj[p];
      const double div = pg[p] * pn[p].dot(v[j] - vi);
      si += div;
      s[j] += div;
    }
    s[i] = si;
  }
  for (std::size_t k = 0; k < step.halo_end; ++k) {
    const std::int32_t i = step.global[k];
    state.pressure[i] =
        sys.press_coef[k] > 0.0
            ? std::max(0.0, model.kappa[i] * (sys.constraint[k] + dt * sys.div[k]))
            : 0.0;
  }
}

}  // namespace

void reactions_and_pressure(const NucleusModel& model, NucleusState& state,
                            NucleusWorkspace& work, double dt, std::span<const Collider> moving,
                            std::span<BodyReaction> reactions) {
  end_of_step_pressures(model, state, work, dt);
  const StepWalls& walls = work.walls;
  const Vec3* v = work.pcg.v.data();
  std::size_t w0 = 0;
  while (w0 < walls.hit_count) {
    // The hits of one particle are consecutive.
    const std::int32_t k = walls.hits[w0].particle;
    const std::int32_t i = work.step.global[k];
    std::size_t end = w0;
    while (end < walls.hit_count && walls.hits[end].particle == k) ++end;
    double share[kMaxWallHitsPerParticle] = {0, 0, 0, 0};
    contact_shares(work, k, w0, end, dt, share);
    for (std::size_t h = w0; h < end; ++h) {
      const WallHit& w = walls.hits[h];
      if (w.collider < 0) {
        // The gathered static (the bone): the same three parts, only recorded.
        if (w.collider == -1 - model.options.gathered_static) {
          Vec3 f = -share[h - w0] * w.normal;
          f += (work.sys.visc_coef[k] * w.visc) * (v[k] - w.v_wall);
          f += model.volume * state.pressure[i] * w.grad;
          state.static_force[i] += f;
        }
        continue;
      }
      const Collider& c = moving[w.collider];
      if (c.body < 0 || static_cast<std::size_t>(c.body) >= reactions.size()) continue;
      BodyReaction& r = reactions[c.body];
      // Force on the body = minus the force on the particle.
      Vec3 f = -share[h - w0] * w.normal;                  // contact
      const Eigen::Matrix3d C = work.sys.visc_coef[k] * w.visc;
      f += C * (v[k] - w.v_wall);                          // no-slip drag
      f += model.volume * state.pressure[i] * w.grad;      // wall pressure (grad points inward)
      r.force_N += f;
      state.body_force[i] += f;
      const Vec3 arm = w.point - r.reference_point;
      r.torque_Nm += arm.cross(f);
      // Trace: an upper bound of the largest eigenvalue of the (PSD) coupling tensor.
      r.drag_Ns_m += C.trace();
      r.rot_drag_Nms += C.trace() * arm.squaredNorm();
    }
    w0 = end;
  }
}

}  // namespace acdr::nucleus
