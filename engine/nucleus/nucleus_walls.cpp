// Walls: the collider frames of a step, the wall hits with the density, second moment and
// no-slip sums of the lattice sites inside each solid (tabulated for flat faces, cached for
// the rest), and the contact constraints. Also the flat-face table the model is built with.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "engine/nucleus/nucleus_math.hpp"
#include "engine/nucleus/nucleus_stages.hpp"

namespace acdr::nucleus {
namespace {

// A particle's static-collider mask (setup_walls) holds while it stays this close (in units
// of h) to where the mask was found.
constexpr double kStaticMaskMargin = 0.25;

// A particle this close (in units of h) beyond the contact distance is held at it even while
// receding by a hair: the contact lets go in the same step if holding it would pull
// (release_pulling_contacts). Left out, a particle resting on a moving wall alternated between
// held and free from step to step (rounding and the wall's motion tip its normal velocity
// either way), and with it the force on the wall.
constexpr double kContactHold = 0.01;

// Wall sums of collider `kc`'s lattice sites around a particle at x (local: x in the
// collider's frame), d from its surface: each site within R counts with its occupancy (see
// setup_walls). The sites are placed in the collider's frame with the offsets rotated once per
// step (collider_frames), and a box's sites farther than h/2 outside its faces along any local
// axis are rejected before the distance (their occupancy is 0): a particle beside the moving
// blade recomputes these sums nearly every step, and most of its sites are outside the blade.
SiteSums site_sums(const NucleusModel& model, const ColliderFrames& frames, const Collider& c,
                   std::int32_t kc, const Vec3& x, const Vec3& local, double d) {
  SiteSums sums;
  const double inv_d_eff = 1.0 / std::max(d, 0.25 * model.h);
  const double inv_n0 = 1.0 / model.n0;
  const double half = 0.5 * model.h;
  const bool identity = frames.identity[kc] != 0;
  const Vec3* offsets =
      identity ? model.sites.offset.data() : &frames.site_local[kc * model.sites.offset.size()];
  const bool box = c.kind == ColliderKind::kBox;
  const Vec3 reject = c.half_extents_m + Vec3::Constant(half);
  Vec3 grad_local = Vec3::Zero();
  for (std::size_t o = 0; o < model.sites.offset.size(); ++o) {
    // sd(site) >= d - |offset|: a site that far cannot be occupied.
    if (d - model.sites.len[o] >= half) continue;
    // An unrotated collider: the site's local point exactly as signed_distance() forms it.
    const Vec3 p = identity ? Vec3((x + model.sites.offset[o]) - c.pose.position)
                            : Vec3(local + offsets[o]);
    if (box && (p.x() >= reject.x() || -p.x() >= reject.x() || p.y() >= reject.y() ||
                -p.y() >= reject.y() || p.z() >= reject.z() || -p.z() >= reject.z()))
      continue;  // sd >= |p_a| - b_a >= h/2 on that axis
    Vec3 nq;
    const double sd = signed_distance_local(c, p, &nq);
    double slope = 0.0;
    const double occ = occupancy(sd, model.h, &slope);
    if (occ <= 0.0) continue;
    sums.n += occ * model.sites.w[o];
    sums.s2 += occ * model.sites.wv[o] * model.sites.r2[o];
    grad_local += (slope * model.sites.w[o] * inv_n0) * nq;
    sums.visc +=
        (occ * model.sites.wv[o] * (1.0 + std::max(0.0, -sd) * inv_d_eff)) * model.sites.uu[o];
  }
  sums.grad = identity ? grad_local : Vec3(c.pose.orientation * grad_local);
  return sums;
}

// site_sums of collider `kc` (index over statics then moving) for particle i at x, from the
// cache while i's position in the collider's frame has moved less than the tolerance and the
// collider has turned less than the tolerance over R since they were computed: the sums are
// a function of that relative placement only (a translated collider carries its sums along;
// the lattice of sites is world-aligned, hence the turn limit).
const SiteSums& cached_site_sums(const NucleusModel& model, const ColliderFrames& frames,
                                 SiteSumCache& site_cache, std::int32_t kc, const Collider& c,
                                 std::int32_t i, const Vec3& x, double d) {
  const double tol = model.solver.wall_sum_cache_tolerance * model.h;
  const Vec3 local = to_local(c.pose, frames.identity[kc] != 0, x);
  SiteSums* entries = &site_cache.entries[kMaxWallHitsPerParticle * static_cast<std::size_t>(i)];
  SiteSums* slot = nullptr;
  for (int e = 0; e < kMaxWallHitsPerParticle; ++e) {
    if (entries[e].collider == kc) slot = &entries[e];
  }
  if (slot) {
    const bool placed = (local - slot->local).squaredNorm() < tol * tol;
    const bool turned =
        !(std::abs(c.pose.orientation.dot(slot->orientation)) > model.cache_turn_cos);
    if (placed && !turned) return *slot;
  } else {
    slot = &entries[site_cache.next[i]];  // round robin over the particle's entries
    site_cache.next[i] =
        static_cast<std::uint8_t>((site_cache.next[i] + 1) % kMaxWallHitsPerParticle);
  }
  *slot = site_sums(model, frames, c, kc, x, local, d);
  slot->collider = kc;
  slot->local = local;
  slot->orientation = c.pose.orientation;
  return *slot;
}

// Whether particle x at distance d sees collider c as one axis-aligned flat face within the
// whole site neighbourhood (a half-space, or a box face far enough from the face's edges and
// thick enough), so the tabulated wall sums apply. `axis` receives the normal's axis.
bool flat_face(const NucleusModel& model, const Collider& c, const Vec3& x, double d,
               const Vec3& normal, int* axis) {
  const Quat& q = c.pose.orientation;
  if (std::abs(std::abs(q.w()) - 1.0) > 1e-12) return false;  // rotated
  int a = -1;
  for (int k = 0; k < 3; ++k)
    if (std::abs(std::abs(normal[k]) - 1.0) < 1e-12) a = k;
  if (a < 0) return false;
  *axis = a;
  if (c.kind == ColliderKind::kHalfSpace) return a == 2;
  if (c.kind != ColliderKind::kBox) return false;
  // The face's extent must cover every site within R (lateral margin R) and the solid must be
  // as deep as the sites reach (R - d; the few sites near the far face then differ from the
  // half-space value by at most a few percent of one site's weight).
  const Vec3 local = x - c.pose.position;
  if (d < 0.0) return false;
  for (int k = 0; k < 3; ++k) {
    if (k == a) continue;
    if (std::abs(local[k]) > c.half_extents_m[k] - model.radius) return false;
  }
  return 2.0 * c.half_extents_m[a] >= model.radius - d;
}

// Builds this step's wall hits, wall sums and contact constraints (see setup_walls).
class WallBuilder {
 public:
  WallBuilder(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work,
              double dt, std::span<const Collider> moving)
      : model_(model), state_(state), work_(work), step_(work.step), sys_(work.sys),
        walls_(work.walls), contacts_(work.contacts), cull_(work.cull), frames_(work.frames),
        moving_(moving), dt_(dt),
        // A lattice site within R of the particle can be inside the solid only if d < R + h/2.
        wall_range_(model.radius + 0.5 * model.h),
        contact_hold_(model.contact + kContactHold * model.h),
        n_static_(model.statics.size()),
        n_coll_(n_static_ + moving.size()) {
    // Bounding boxes and speed bounds of the colliders.
    for (std::size_t c = 0; c < n_coll_; ++c) {
      const Collider& col = c < n_static_ ? model.statics[c] : moving[c - n_static_];
      bounded_[c] = model.solver.contact_culling && collider_bounds(col, &lo_[c], &hi_[c]);
    }
  }

  void clear() {
    walls_.hit_count = 0;
    walls_.particles = 0;
    contacts_.particles = 0;
    for (std::size_t k = 0; k < step_.halo_end; ++k) {
      sys_.density[k] = 0.0;
      sys_.second_moment[k] = 0.0;
      walls_.slot[k] = -1;
    }
    for (std::size_t k = 0; k < step_.awake_end; ++k) {
      contacts_.slot[k] = -1;
      cull_.near_colliders[k] = 0;
      cull_.all_colliders[k] = model_.solver.contact_culling ? 0 : 1;
    }
  }

  void walls_of_every_particle() {
    // Static colliders per particle. A static collider whose lower distance bound (box gap,
    // the exact distance of a half-space, the bone's sampled distance less what it can change
    // beyond a 1-Lipschitz bound over the margin) was at least wall_range + margin where the
    // mask was found is at least wall_range away while the particle stays within the margin of
    // that place (distances are 1-Lipschitz); when also the contact reach bound is inside the
    // wall range (|v| dt <= wall_range - contact - 0.1 h), the test below would skip it, so it
    // is left out without evaluating anything (bit-identical).
    const double mask_margin = kStaticMaskMargin * model_.h;
    const double mask_margin2 = mask_margin * mask_margin;
    const double mask_far = wall_range_ * (1.0 + 1e-9) + 1e-6 * model_.h + mask_margin;
    const double slow_reach = wall_range_ - model_.contact - 0.1 * model_.h;
    const double slow_v2 = slow_reach > 0.0 ? (slow_reach / dt_) * (slow_reach / dt_) : -1.0;
    const std::uint32_t all_statics = n_static_ >= 32 ? ~0u : ((1u << n_static_) - 1u);
    const std::uint32_t moving_bits =
        (n_coll_ >= 32 ? ~0u : ((1u << n_coll_) - 1u)) & ~all_statics;
    for (std::size_t k = 0; k < step_.halo_end; ++k) {
      const std::int32_t i = step_.global[k];
      const Vec3 xi = state_.x[i];
      const Vec3 vi = state_.v[i];
      std::uint32_t statics_mask = all_statics;
      if (model_.solver.contact_culling && vi.squaredNorm() <= slow_v2 * (1.0 - 1e-9)) {
        if (!((xi - cull_.static_ref[i]).squaredNorm() <= mask_margin2)) {
          cull_.static_mask[i] = statics_near(xi, mask_far, mask_margin);
          cull_.static_ref[i] = xi;
        }
        statics_mask = cull_.static_mask[i];
      }
      particle_walls(k, statics_mask | moving_bits);
    }
  }

 private:
  // The static colliders whose lower distance bound from x is below `far` (bit k: static k),
  // the bound taken as 1-Lipschitz over the `margin` around x.
  std::uint32_t statics_near(const Vec3& xi, double far, double margin) const {
    std::uint32_t mask = 0;
    for (std::size_t kc = 0; kc < n_static_; ++kc) {
      const Collider& c = model_.statics[kc];
      double gap = 0.0;  // lower bound of the distance to the solid
      if (bounded_[kc]) {
        gap = box_gap(xi, lo_[kc], hi_[kc]);
      } else if (c.kind == ColliderKind::kHalfSpace) {
        gap = signed_distance_local(c, to_local(c.pose, frames_.identity[kc] != 0, xi), nullptr);
      } else if (c.kind == ColliderKind::kSdfGrid) {
        // The sampled bone changes by at most slope x margin over the margin, where a
        // 1-Lipschitz bound would change by the margin: the excess comes off its value here.
        // One lookup per mask instead of one per particle and step.
        const double d =
            signed_distance_local(c, to_local(c.pose, frames_.identity[kc] != 0, xi), nullptr);
        gap = d - (distance_slope_bound(c) - 1.0) * margin;
      }
      if (!(gap >= far)) mask |= 1u << kc;
    }
    return mask;
  }

  // Local particle k's hits on the colliders of `todo` (bit per collider), its wall sums, and
  // for an awake particle its contact constraint.
  void particle_walls(std::size_t k, std::uint32_t todo) {
    const std::int32_t i = step_.global[k];
    const bool awake = k < step_.awake_end;
    const Vec3 xi = state_.x[i];
    const Vec3 vi = state_.v[i];
    const double vi_norm = vi.norm();
    int hits = 0;
    Vec3 grad_sum = Vec3::Zero();
    // This particle's hits start here; up to 3 of them are contacts.
    const std::size_t first_hit = walls_.hit_count;
    int nc = 0;
    // The colliders to look at (the statics in the mask, every moving one), in index order.
    for (; todo != 0; todo &= todo - 1) {
      const std::size_t kc = static_cast<std::size_t>(__builtin_ctz(todo));
      const Collider& c = kc < n_static_ ? model_.statics[kc] : moving_[kc - n_static_];
      if (bounded_[kc]) {
        // The surface is at least box_gap away; the contact reach is at most
        // contact + 0.1 h + |v_i - v_wall| dt. (Compared squared: the bound has a 1e-9 margin,
        // and a collider kept by rounding is skipped by the exact test below.)
        const double v_wall =
            kc < n_static_ ? 0.0
                           : frames_.lin_speed[kc] +
                                 (frames_.ang_speed[kc] != 0.0
                                      ? frames_.ang_speed[kc] * (xi - c.pose.position).norm()
                                      : 0.0);
        const double reach_bound = model_.contact + 0.1 * model_.h + (vi_norm + v_wall) * dt_;
        const double bound = std::max(wall_range_, reach_bound) * (1.0 + 1e-9);
        if (box_gap2(xi, lo_[kc], hi_[kc]) >= bound * bound) continue;
      }
      Vec3 normal;
      const bool unrotated = frames_.identity[kc] != 0;
      const double d = signed_distance_local(c, to_local(c.pose, unrotated, xi), &normal);
      if (!unrotated) normal = c.pose.orientation * normal;
      const Vec3 vw = kc < n_static_ ? Vec3::Zero() : c.velocity_at(xi);
      const double vn_rel = (vi - vw).dot(normal);
      const double reach = model_.contact + 0.1 * model_.h + std::max(0.0, -vn_rel) * dt_;
      if (d >= wall_range_ && d >= reach) continue;
      if (hits >= kMaxWallHitsPerParticle || walls_.hit_count >= walls_.hits.size()) {
        if (awake) cull_.all_colliders[k] = 1;  // not tracked: the projection checks everything
        continue;
      }
      ++hits;
      if (awake) cull_.near_colliders[k] |= 1u << kc;
      WallHit& w = walls_.hits[walls_.hit_count++];
      w.particle = static_cast<std::int32_t>(k);
      w.collider = kc < n_static_ ? -1 - static_cast<std::int32_t>(kc)
                                  : static_cast<std::int32_t>(kc - n_static_);
      w.normal = normal;
      w.v_wall = vw;
      w.point = xi - d * normal;
      w.distance = d;
      add_wall_sums(w, k, i, c, kc, xi, d, unrotated);
      grad_sum += w.grad;
      // Contact constraint: approaching particles within reach and those at the contact
      // distance. The normal velocity is set to what brings the particle exactly to the contact
      // distance, or to its current normal velocity if that is slower (no pull toward the
      // wall); a contact that would still pull lets go after the solve and the step solves
      // again (release_pulling_contacts). Penetrating particles are stopped in the normal
      // direction and pushed out by position after the solve.
      w.contact = false;
      if (awake && d < reach && (vn_rel <= 1e-12 || d <= contact_hold_) && nc < 3) {
        const double approach = d > model_.contact ? -(d - model_.contact) / dt_ : 0.0;
        w.contact_target = vw.dot(normal) + std::max(approach, std::min(vn_rel, 0.0));
        ++nc;
        w.contact = true;
      }
    }
    if (hits > 0) {
      const std::size_t slot = walls_.particles++;
      walls_.slot[k] = static_cast<std::int32_t>(slot);
      walls_.particle[slot] = static_cast<std::int32_t>(k);
      walls_.g[slot] = grad_sum;
      walls_.c[slot] = Eigen::Matrix3d::Zero();
    }
    if (!awake) return;
    if (nc > 0) add_contact_constraint(k, first_hit);
  }

  // The solid fills the lattice sites a particle is missing near it: their density, its
  // gradient, and their second moment are counted as neighbours (the role of boundary
  // particles in Akinci et al. 2012), site by site from the signed distance, so edges,
  // corners and thin shells count what is really solid.
  //
  // No-slip: the solid's sites also enter the viscous sum, each moving with the mirrored
  // velocity v_w - (d_site / d)(v_i - v_w) of Morris, Fox & Zhu (J Comput Phys 1997), which
  // extends the particle's velocity profile linearly through the wall to the wall velocity
  // at the surface. A site's pair term then couples the particle to the wall velocity with
  // (1 + d_site / d) times its weight: the tensor `visc` (scaled by the particle's viscous
  // coefficient in assemble()). On the lattice this is mu A / d for the first layer.
  void add_wall_sums(WallHit& w, std::size_t k, std::int32_t i, const Collider& c,
                     std::size_t kc, const Vec3& xi, double d, bool unrotated) {
    int face_axis = -1;
    if (d < wall_range_ && flat_face(model_, c, xi, d, w.normal, &face_axis)) {
      // An axis-aligned flat face seen by every site: the sums depend on d only (table).
      const WallTableEntry e = model_.wall_table.at(d);
      sys_.density[k] += e.n;
      sys_.second_moment[k] += e.s2;
      w.grad = e.grad * w.normal;
      w.visc = e.visc_t * Eigen::Matrix3d::Identity();
      w.visc(face_axis, face_axis) = e.visc_n;
    } else if (d < wall_range_) {
      // The sums depend on where the particle is relative to the solid only (cached; read
      // in place, not copied).
      SiteSums uncached;
      const SiteSums& sums =
          model_.solver.wall_sum_cache
              ? cached_site_sums(model_, frames_, work_.site_cache,
                                 static_cast<std::int32_t>(kc), c, i, xi, d)
              : (uncached = site_sums(model_, frames_, c, static_cast<std::int32_t>(kc), xi,
                                      to_local(c.pose, unrotated, xi), d));
      sys_.density[k] += sums.n;
      sys_.second_moment[k] += sums.s2;
      w.grad = sums.grad;
      w.visc = sums.visc;
    } else {
      w.grad = Vec3::Zero();  // beyond the wall range: only a contact
      w.visc = Eigen::Matrix3d::Zero();
    }
    if (c.slip) w.visc = Eigen::Matrix3d::Zero();  // the gel slides on it (Collider::slip)
  }

  // Local particle k's contact slot, from its contact hits (from first_hit on).
  void add_contact_constraint(std::size_t k, std::size_t first_hit) {
    const std::size_t slot = contacts_.particles++;
    contacts_.slot[k] = static_cast<std::int32_t>(slot);
    contacts_.particle[slot] = static_cast<std::int32_t>(k);
    constrain_contact_hits(contacts_, slot, walls_.hits.data(), first_hit, walls_.hit_count);
  }

  const NucleusModel& model_;
  NucleusState& state_;
  NucleusWorkspace& work_;
  StepParticles& step_;
  StepSystem& sys_;
  StepWalls& walls_;
  StepContacts& contacts_;
  ColliderCulling& cull_;
  const ColliderFrames& frames_;
  std::span<const Collider> moving_;
  const double dt_;
  const double wall_range_;
  const double contact_hold_;
  const std::size_t n_static_, n_coll_;
  std::array<Vec3, kMaxStepColliders> lo_, hi_;
  std::array<bool, kMaxStepColliders> bounded_;
};

}  // namespace

// Walls: for each particle of the step near a collider, the no-slip coupling, the density and
// second moment of the lattice sites inside the solid, and the contact constraint. A collider
// whose bounding box is farther than any of these reach is skipped (its surface is at least
// that far), unless culling is switched off.
void setup_walls(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work,
                 double dt, std::span<const Collider> moving) {
  WallBuilder builder(model, state, work, dt, moving);
  builder.clear();
  builder.walls_of_every_particle();
}

// Per collider of this step (statics, then moving): its linear and angular speed, whether its
// orientation is the identity, and otherwise the lattice site offsets in its frame.
void collider_frames(const NucleusModel& model, ColliderFrames& frames,
                     std::span<const Collider> moving) {
  const std::size_t n_static = model.statics.size();
  const std::size_t sites = model.sites.offset.size();
  for (std::size_t kc = 0; kc < n_static + moving.size(); ++kc) {
    const Collider& c = kc < n_static ? model.statics[kc] : moving[kc - n_static];
    frames.lin_speed[kc] = c.linear_velocity_m_s.norm();
    frames.ang_speed[kc] = c.angular_velocity_rad_s.norm();
    const Quat& q = c.pose.orientation;
    const bool identity = q.w() == 1.0 && q.x() == 0.0 && q.y() == 0.0 && q.z() == 0.0;
    frames.identity[kc] = identity ? 1 : 0;
    if (identity) continue;
    const Eigen::Matrix3d to_local = q.conjugate().toRotationMatrix();
    for (std::size_t o = 0; o < sites; ++o)
      frames.site_local[kc * sites + o] = to_local * model.sites.offset[o];
  }
}

// Wall sums of a flat face normal to +z at distance d, sampled over [-h/2, R + h/2].
void build_wall_table(NucleusModel& model) {
  const int samples = static_cast<int>(model.wall_table.entries.size());
  const double lo = -0.5 * model.h, hi = model.radius + 0.5 * model.h;
  model.wall_table.step = (hi - lo) / (samples - 1);
  model.wall_table.lo = lo;
  for (int k = 0; k < samples; ++k) {
    const double d = lo + k * model.wall_table.step;
    const double d_eff = std::max(d, 0.25 * model.h);
    WallTableEntry e{};
    for (std::size_t o = 0; o < model.sites.offset.size(); ++o) {
      const double sd = d + model.sites.offset[o].z();
      double slope = 0.0;
      const double occ = occupancy(sd, model.h, &slope);
      if (occ <= 0.0) continue;
      const Vec3 u = model.sites.offset[o] / model.sites.len[o];
      const double vw = occ * model.sites.wv[o] * (1.0 + std::max(0.0, -sd) / d_eff);
      e.n += occ * model.sites.w[o];
      e.s2 += occ * model.sites.wv[o] * model.sites.r2[o];
      e.grad += slope * model.sites.w[o] / model.n0;
      e.visc_n += vw * u.z() * u.z();
      e.visc_t += vw * u.x() * u.x();
    }
    model.wall_table.entries[k] = e;
  }
}

}  // namespace acdr::nucleus
