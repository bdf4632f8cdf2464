// Contacts: the velocity constraints that keep particles at the contact distance from the
// colliders, their forces, and the release of those that would pull. A contact only pushes:
// a wall that would have to pull a particle to hold it lets go in the same step (an active
// set over the step's solves), so the set of touching particles follows the solution instead
// of lagging it by a step, which made the force alternate from step to step.
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "engine/nucleus/nucleus_stages.hpp"

namespace acdr::nucleus {
namespace {

// Solves per step at most: the first, and again while contacts let go. Each later solve starts
// from the last one's velocities; a contact that still pulls after the last keeps its force.
constexpr int kContactSolves = 3;

}  // namespace

unsigned set_contact_constraint(StepContacts& contacts, std::size_t slot, const Vec3* cn,
                                const double* ct, int nc) {
  Vec3 e[3];
  Vec3 used_n[3];
  double used_t[3];
  int ne = 0;
  unsigned used = 0;
  for (int a = 0; a < nc; ++a) {
    // A wall facing one already taken (a particle squeezed between them, normals more than
    // 120 degrees apart) is left out: the two targets cannot both hold, and solved together
    // they asked for a large velocity along the gap and a force to match on the walls. The
    // first wall wins (the statics come first), as in the projection after the solve.
    bool opposed = false;
    for (int b = 0; b < ne; ++b) opposed = opposed || used_n[b].dot(cn[a]) < -0.5;
    if (opposed) continue;
    Vec3 u = cn[a];
    for (int b = 0; b < ne; ++b) u -= e[b] * e[b].dot(u);
    const double len = u.norm();
    if (len < 0.2) continue;  // nearly parallel to one already taken
    e[ne] = u / len;
    used_n[ne] = cn[a];
    used_t[ne] = ct[a];
    used |= 1u << a;
    ++ne;
  }
  Vec3 vc = Vec3::Zero();
  if (ne == 1) {
    vc = used_t[0] * used_n[0];
  } else if (ne == 2) {
    Eigen::Matrix2d G2;
    G2 << 1.0, used_n[0].dot(used_n[1]), used_n[0].dot(used_n[1]), 1.0;
    const Eigen::Vector2d a2 = G2.inverse() * Eigen::Vector2d(used_t[0], used_t[1]);
    vc = a2[0] * used_n[0] + a2[1] * used_n[1];
  } else if (ne == 3) {
    Eigen::Matrix3d G3;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) G3(a, b) = used_n[a].dot(used_n[b]);
    const Vec3 a3 = G3.inverse() * Vec3(used_t[0], used_t[1], used_t[2]);
    vc = a3[0] * used_n[0] + a3[1] * used_n[1] + a3[2] * used_n[2];
  }
  contacts.count[slot] = static_cast<std::uint8_t>(ne);
  for (int a = 0; a < ne; ++a) contacts.e[slot][a] = e[a];
  contacts.v[slot] = vc;
  return used;
}

void constrain_contact_hits(StepContacts& contacts, std::size_t slot, WallHit* hits,
                            std::size_t w0, std::size_t end) {
  Vec3 cn[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  double ct[3] = {0.0, 0.0, 0.0};  // only [0, nc) of these is read; set so GCC sees that
  WallHit* ch[3];
  int nc = 0;
  for (std::size_t h = w0; h < end && nc < 3; ++h) {
    if (!hits[h].contact) continue;
    cn[nc] = hits[h].normal;
    ct[nc] = hits[h].contact_target;
    ch[nc] = &hits[h];
    ++nc;
  }
  const unsigned used = set_contact_constraint(contacts, slot, cn, ct, nc);
  for (int a = 0; a < nc; ++a)
    if (!(used & (1u << a))) ch[a]->contact = false;
}

int contact_shares(const NucleusWorkspace& work, std::int32_t k, std::size_t w0,
                   std::size_t end, double dt, double* share) {
  const StepContacts& contacts = work.contacts;
  const StepWalls& walls = work.walls;
  const std::int32_t cs =
      k < static_cast<std::int32_t>(work.step.awake_end) ? contacts.slot[k] : -1;
  if (cs < 0) return 0;
  Vec3 lambda = (contacts.av[cs] - work.sys.rhs[k]) / dt;
  Vec3 constrained = Vec3::Zero();
  for (int a = 0; a < contacts.count[cs]; ++a)
    constrained += contacts.e[cs][a] * contacts.e[cs][a].dot(lambda);
  lambda = constrained;
  int idx[3];
  int nc = 0;
  for (std::size_t h = w0; h < end && nc < 3; ++h)
    if (walls.hits[h].contact) idx[nc++] = static_cast<int>(h - w0);
  if (nc == 1) {
    share[idx[0]] = lambda.dot(walls.hits[w0 + idx[0]].normal);
  } else if (nc > 1) {
    Eigen::Matrix3d G = Eigen::Matrix3d::Identity();
    Vec3 rhs = Vec3::Zero();
    for (int a = 0; a < nc; ++a) {
      rhs[a] = walls.hits[w0 + idx[a]].normal.dot(lambda);
      for (int b = 0; b < nc; ++b)
        G(a, b) = walls.hits[w0 + idx[a]].normal.dot(walls.hits[w0 + idx[b]].normal);
    }
    const Vec3 sol = G.ldlt().solve(rhs);
    for (int a = 0; a < nc; ++a) share[idx[a]] = std::isfinite(sol[a]) ? sol[a] : 0.0;
  }
  int pulling = 0;
  for (int a = 0; a < nc; ++a) pulling += share[idx[a]] < 0.0 ? 1 : 0;
  return pulling;
}

int release_pulling_contacts(NucleusWorkspace& work, double dt) {
  StepWalls& walls = work.walls;
  int released = 0;
  std::size_t w0 = 0;
  while (w0 < walls.hit_count) {
    // The hits of one particle are consecutive.
    const std::int32_t k = walls.hits[w0].particle;
    std::size_t end = w0;
    while (end < walls.hit_count && walls.hits[end].particle == k) ++end;
    double share[kMaxWallHitsPerParticle] = {0, 0, 0, 0};
    if (contact_shares(work, k, w0, end, dt, share) > 0) {
      for (std::size_t h = w0; h < end; ++h) {
        WallHit& w = walls.hits[h];
        if (w.contact && share[h - w0] < 0.0) {
          w.contact = false;
          ++released;
        }
      }
      constrain_contact_hits(work.contacts, static_cast<std::size_t>(work.contacts.slot[k]),
                             walls.hits.data(), w0, end);
    }
    w0 = end;
  }
  return released;
}

void solve_with_contacts(const NucleusModel& model, NucleusState& state, NucleusWorkspace& work,
                         double dt, NumericalReport& report) {
  solve_velocities(model, state, work, report);
  for (int solve = 1; solve < kContactSolves && report.ok; ++solve) {
    if (release_pulling_contacts(work, dt) == 0) break;
    NumericalReport again;
    solve_velocities(model, state, work, again, /*resume=*/true);
    report.iterations += again.iterations;
    report.residual = again.residual;
    if (!again.ok) {
      report.ok = false;
      report.stage = again.stage;
    }
  }
}

}  // namespace acdr::nucleus
