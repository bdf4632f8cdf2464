// Integration and projection: positions, then the swept contact projection: each particle
// path is followed in the collider's frame from its start-of-step pose to its end-of-step
// pose; a path that enters the (h/2-inflated) solid is stopped on the side it came from. A
// collider whose surface was beyond the wall range at the start of the step is skipped when
// the path (relative to the collider) is shorter than the gap: the path cannot reach the
// inflated surface. Last, the periodic wrap.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "engine/nucleus/nucleus_math.hpp"
#include "engine/nucleus/nucleus_stages.hpp"

namespace acdr::nucleus {
namespace {

class Projector {
 public:
  Projector(const NucleusModel& model, NucleusState& state, const NucleusWorkspace& work,
            double dt, std::span<const Collider> moving, std::span<BodyReaction> reactions)
      : model_(model), state_(state), step_(work.step), walls_(work.walls), cull_(work.cull),
        frames_(work.frames), moving_(moving), reactions_(reactions), dt_(dt),
        n_static_(model.statics.size()), n_all_(n_static_ + moving.size()),
        tiny_(1e-4 * model.h),
        free_path_(model.radius + 0.5 * model.h - model.contact - 0.01 * model.h),
        static_bits_(n_static_ >= 32 ? ~0u : ((1u << n_static_) - 1u)) {}

  // Awake particle k against every collider it may reach. Statics, then the moving bodies,
  // then the statics again: a particle squeezed between the instrument and a wall ends on the
  // wall's side (walls and bone are never crossed; an overlap with the instrument is pushed
  // out over the next steps). `hit_cursor`: walls.hits holds each particle's hits
  // consecutively, by local index; it is moved to k's first hit.
  void project(std::size_t k, std::size_t& hit_cursor) {
    const std::int32_t i = step_.global[k];
    const std::uint32_t near_mask = cull_.near_colliders[k];
    const bool check_all = cull_.all_colliders[k] != 0;
    const std::int32_t kk = static_cast<std::int32_t>(k);
    while (hit_cursor < walls_.hit_count && walls_.hits[hit_cursor].particle < kk) ++hit_cursor;
    std::size_t hit_end = hit_cursor;
    while (hit_end < walls_.hit_count && walls_.hits[hit_end].particle == kk) ++hit_end;
    double moved = (state_.x[i] - step_.x_start[i]).norm();  // kept current as x moves
    // The statics' second round sees the same position, path and hits as their first when no
    // collider moved the particle in between: it would find nothing either (skipped).
    bool projected = false;
    const std::size_t n_pass = n_all_ + (moving_.empty() ? 0 : n_static_);
    // The first pass from `pass` on that can find anything: a static collider the particle was
    // not near is skipped below while its path (the particle's own displacement, the same for
    // every static) is free, so those passes are stepped over at once with the near mask.
    auto next_pass = [&](std::size_t pass) -> std::size_t {
      if (check_all || !(moved < free_path_)) return pass;
      const std::size_t base = pass < n_all_ ? 0 : n_all_;
      const std::size_t c_idx = pass - base;
      if (c_idx >= n_static_) return pass;
      const std::uint32_t rest = near_mask & static_bits_ & (~0u << c_idx);
      return rest ? base + static_cast<std::size_t>(__builtin_ctz(rest)) : base + n_static_;
    };
    for (std::size_t pass = next_pass(0); pass < n_pass; pass = next_pass(pass + 1)) {
      if (pass >= n_all_ && !projected) break;
      const std::size_t c_idx = pass < n_all_ ? pass : pass - n_all_;
      const bool is_static = c_idx < n_static_;
      const Collider& c = is_static ? model_.statics[c_idx] : moving_[c_idx - n_static_];
      if (!check_all && !(near_mask & (1u << c_idx))) {
        // Path length in the collider's frame: the particle's displacement plus how far the
        // collider's material near it moved (|v| dt + |w| dt * distance).
        double path = moved;
        if (!is_static)
          path += (frames_.lin_speed[c_idx] +
                   frames_.ang_speed[c_idx] * (step_.x_start[i] - c.pose.position).norm()) *
                  dt_ * 1.01;
        if (path < free_path_) continue;
      }
      if (!sweep(c, c_idx, i, hit_cursor, hit_end)) continue;
      moved = (state_.x[i] - step_.x_start[i]).norm();
      projected = true;
    }
  }

 private:
  // Particle i's path against collider c (index c_idx over statics then moving; its hits of
  // this step in [hit_begin, hit_end)); true when the particle was put back outside.
  bool sweep(const Collider& c, std::size_t c_idx, std::int32_t i, std::size_t hit_begin,
             std::size_t hit_end) {
    const bool is_static = c_idx < n_static_;
    const Pose& start = c.pose;
    const Pose& end = is_static ? c.pose : frames_.end_pose[c_idx - n_static_];
    const bool start_unrotated = frames_.identity[c_idx] != 0;
    const bool end_unrotated =
        is_static ? start_unrotated : frames_.end_identity[c_idx - n_static_] != 0;
    const Vec3 p0 = to_local(start, start_unrotated, step_.x_start[i]);
    Vec3 p1 = to_local(end, end_unrotated, state_.x[i]);
    const double len = (p1 - p0).norm();
    // The start distance is the one setup_walls found for this particle's hit on c (the same
    // evaluation). The distance changes by at most slope x len along the path (slope 1 for an
    // exact distance, more for the sampled bone), so when slope x len <= d0 - contact -
    // 2 tiny the path can neither end inside nor cross the inflated surface (d1 >= d0 -
    // slope len, and d0 + d1 - 2 contact >= len): the test below would pass, skip both
    // distances.
    const std::int32_t hit_id = is_static ? -1 - static_cast<std::int32_t>(c_idx)
                                          : static_cast<std::int32_t>(c_idx - n_static_);
    std::size_t h = hit_begin;
    while (h < hit_end && walls_.hits[h].collider != hit_id) ++h;
    const bool known = h < hit_end;
    if (known && distance_slope_bound(c) * len <=
                     walls_.hits[h].distance - model_.contact - 2.0 * tiny_)
      return false;
    Vec3 n1;
    const double d1 = signed_distance_local(c, p1, &n1);
    Vec3 n0;
    const double d0 = known ? walls_.hits[h].distance : signed_distance_local(c, p0, &n0);
    // The path cannot reach the inflated surface (triangle inequality on distances).
    if (d1 >= model_.contact - tiny_ && len <= d0 + d1 - 2.0 * model_.contact) return false;
    Vec3 normal;   // local normal of the face the particle is held on
    Vec3 surface;  // a local point of that face
    if (!entry_face(c, p0, p1, len, known, d0, n0, d1, n1, &normal, &surface)) return false;
    // Put the particle on the entry face's plane at the contact distance, keeping its
    // tangential motion; if that is still inside (a corner), step back to the entry side.
    const double contact = model_.contact;
    Vec3 q = p1 + std::max(0.0, contact - (p1 - surface).dot(normal)) * normal;
    Vec3 nq;
    const double dq = signed_distance_local(c, q, &nq);
    if (dq < contact - tiny_) {
      if (dq > -contact && nq.dot(normal) > 0.0) q += (contact - dq) * nq;
      else q = surface + contact * normal;
    }
    state_.x[i] = end.apply(q);
    stop_approach(i, c_idx, end.orientation * normal);
    return true;
  }

  // The face the path p0 -> p1 (local, length len) entered the inflated solid by: its local
  // normal and a local point on it; false when the path stays outside.
  bool entry_face(const Collider& c, const Vec3& p0, const Vec3& p1, double len, bool known,
                  double d0, Vec3& n0, double d1, const Vec3& n1, Vec3* normal,
                  Vec3* surface) const {
    const double contact = model_.contact;
    if (d0 < contact) {
      // Started in contact: the exit side is the start side.
      if (d1 >= contact - tiny_) return false;
      if (known) signed_distance_local(c, p0, &n0);  // the start normal, in the local frame
      *normal = n0;
      *surface = p0 - d0 * n0;
      return true;
    }
    // Sphere-trace the path against the inflated distance.
    const Vec3 u = (p1 - p0) / std::max(len, 1e-300);
    double t = 0.0;
    for (int it = 0; it < 64 && t < len; ++it) {
      Vec3 nn;
      const double d = signed_distance_local(c, p0 + t * u, &nn) - contact;
      if (d < tiny_) {
        *normal = nn;
        *surface = p0 + t * u - (d + contact) * nn;
        return true;
      }
      t += d;
    }
    if (d1 >= contact - tiny_) return false;
    *normal = n1;  // ended inside without a traced entry (grazing): use the end normal
    *surface = p1 - d1 * n1;
    return true;
  }

  // Removes particle i's approaching normal velocity relative to the surface (world normal
  // nw of collider c_idx); its impulse is a force on the collider's body.
  void stop_approach(std::int32_t i, std::size_t c_idx, const Vec3& nw) {
    const bool is_static = c_idx < n_static_;
    const Vec3 vw =
        is_static ? Vec3::Zero() : moving_[c_idx - n_static_].velocity_at(state_.x[i]);
    const double vn = (state_.v[i] - vw).dot(nw);
    if (!(vn < 0.0)) return;
    state_.v[i] -= vn * nw;
    if (is_static) {
      if (static_cast<int>(c_idx) == model_.options.gathered_static)
        state_.static_force[i] += model_.mass[i] * vn / dt_ * nw;
      return;
    }
    const Collider& mc = moving_[c_idx - n_static_];
    if (mc.body < 0 || static_cast<std::size_t>(mc.body) >= reactions_.size()) return;
    BodyReaction& r = reactions_[mc.body];
    const Vec3 f = model_.mass[i] * vn / dt_ * nw;  // minus the particle's momentum change rate
    r.force_N += f;
    state_.body_force[i] += f;
    r.torque_Nm += (state_.x[i] - r.reference_point).cross(f);
  }

  const NucleusModel& model_;
  NucleusState& state_;
  const StepParticles& step_;
  const StepWalls& walls_;
  const ColliderCulling& cull_;
  const ColliderFrames& frames_;
  std::span<const Collider> moving_;
  std::span<BodyReaction> reactions_;
  const double dt_;
  const std::size_t n_static_, n_all_;
  const double tiny_;
  const double free_path_;
  const std::uint32_t static_bits_;
};

void wrap_periodic(const NucleusModel& model, NucleusState& state, const StepParticles& step) {
  for (int a = 0; a < 3; ++a) {
    if (!model.options.periodic[a]) continue;
    const double lo = model.options.periodic_min_m[a];
    const double L = model.options.periodic_max_m[a] - lo;
    for (std::size_t k = 0; k < step.awake_end; ++k) {
      const std::int32_t i = step.global[k];
      state.x[i][a] = lo + (state.x[i][a] - lo) - L * std::floor((state.x[i][a] - lo) / L);
    }
  }
}

}  // namespace

void integrate_and_project(const NucleusModel& model, NucleusState& state,
                           const NucleusWorkspace& work, double dt,
                           std::span<const Collider> moving, std::span<BodyReaction> reactions) {
  const StepParticles& step = work.step;
  for (const std::int32_t i : state.kinematic_list) state.x[i] += dt * state.fixed_v[i];
  for (std::size_t k = 0; k < step.awake_end; ++k) {
    const std::int32_t i = step.global[k];
    state.x[i] += dt * state.v[i];
  }
  Projector projector(model, state, work, dt, moving, reactions);
  std::size_t hit_cursor = 0;
  for (std::size_t k = 0; k < step.awake_end; ++k) projector.project(k, hit_cursor);
  wrap_periodic(model, state, step);
}

}  // namespace acdr::nucleus
