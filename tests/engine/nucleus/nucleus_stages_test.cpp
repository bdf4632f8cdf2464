// The nucleus's stages one by one, on the box module's scene at 3 mm spacing (about 200
// particles, part of them asleep, the blade pressing in): the operator against the dense
// matrix it defines, the PCG's residual, and each stage's invariants.
#include "engine/nucleus/nucleus_stages.hpp"

#include <algorithm>
#include <cstdio>
#include <set>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "tests/engine/nucleus/same_pairs.hpp"
#include "verification/box_block_scene.hpp"

namespace acdr::nucleus {
namespace {

constexpr double kDt = 1e-3;

// A nucleus as model, state and workspace, stepped stage by stage in the order of
// Nucleus::step (the first test checks that the order is the same).
struct StagedNucleus {
  NucleusModel model;
  NucleusState state;
  NucleusWorkspace work;

  StagedNucleus(const NucleusConfig& config, const SolverConfig& solver, const Vec3& gravity,
                std::span<const Collider> statics, const NucleusOptions& options = {}) {
    model.config = config;
    model.solver = solver;
    model.options = options;
    model.gravity = gravity;
    const NucleusParticleSetup setup = lattice_setup(config, options, statics);
    build_model(model, statics, setup);
    init_state(model, setup, state);
    reserve_workspace(model, work);
  }

  // The stages before the solve.
  void up_to_assembly(std::span<const Collider> moving) {
    begin_step(state, work, moving, kDt);
    update_verlet_grid(model, state, work.rows);
    wake_and_sleep(model, state, work, moving, kDt);
    build_pairs(model, state, work);
    collider_frames(model, work.frames, moving);
    setup_walls(model, state, work, kDt, moving);
    assemble(model, state, work, kDt);
  }
  // The stages from the solve on.
  void from_solve(std::span<const Collider> moving, std::span<BodyReaction> reactions,
                  NumericalReport& report) {
    solve_with_contacts(model, state, work, kDt, report);
    reactions_and_pressure(model, state, work, kDt, moving, reactions);
    integrate_and_project(model, state, work, kDt, moving, reactions);
    break_bonds(model, state, work);
  }
  void step(std::span<const Collider> moving, std::span<BodyReaction> reactions) {
    for (auto& r : reactions) {  // as Nucleus::step clears them
      r.force_N = Vec3::Zero();
      r.torque_Nm = Vec3::Zero();
      r.drag_Ns_m = 0.0;
      r.rot_drag_Nms = 0.0;
    }
    NumericalReport report;
    up_to_assembly(moving);
    from_solve(moving, reactions, report);
  }
  std::size_t awake() const { return work.step.awake_end; }
};

// The box scene at 3 mm, waking particles only within a spacing of the blade.
BoxBlockScene pressed_block_scene() {
  BoxBlockScene scene = make_box_block_scene(3e-3);
  scene.solver.sleep_distance_m = 3e-3;
  return scene;
}

// That scene settled until every particle sleeps, then the blade pressing in for 5 steps
// (about 140 of 180 particles awake, the rest in the halo).
struct PressedBlock {
  BoxBlockScene scene = pressed_block_scene();
  StagedNucleus n{scene.nucleus, scene.solver, scene.gravity, scene.statics};
  Collider blade = scene.blade;
  BodyReaction reaction;

  PressedBlock() {
    for (int s = 0; s < 400; ++s) n.step({}, {});
    blade.pose.position.z() = 0.014;  // its face at the contact distance of the top layer
    blade.linear_velocity_m_s = Vec3(0.0, 0.0, -0.1);
    for (int s = 0; s < 5; ++s) advance();
  }
  std::span<const Collider> moving() const { return {&blade, 1}; }
  std::span<BodyReaction> reactions() { return {&reaction, 1}; }
  void advance() {
    reaction.reference_point = blade.pose.position;
    n.step(moving(), reactions());
    blade.pose.position += kDt * blade.linear_velocity_m_s;
  }
};

// The constrained directions of the contact particles removed from u (the PCG's filter).
void filter(const StepContacts& contacts, std::vector<Vec3>& u) {
  for (std::size_t c = 0; c < contacts.particles; ++c) {
    const std::int32_t k = contacts.particle[c];
    for (int a = 0; a < contacts.count[c]; ++a)
      u[k] -= contacts.e[c][a] * contacts.e[c][a].dot(u[k]);
  }
}

// The system matrix on the awake rows, column by column: A e_j for every unit vector.
Eigen::MatrixXd dense_operator(NucleusWorkspace& work) {
  const std::size_t na = work.step.awake_end;
  const std::size_t nl = work.step.outer_end;
  Eigen::MatrixXd A(3 * na, 3 * na);
  std::vector<Vec3> x(nl, Vec3::Zero()), y(nl, Vec3::Zero());
  for (std::size_t col = 0; col < 3 * na; ++col) {
    x[col / 3][col % 3] = 1.0;
    apply_operator(work, work.apply, x.data(), y.data(), false);
    x[col / 3][col % 3] = 0.0;
    for (std::size_t k = 0; k < na; ++k) A.block<3, 1>(3 * k, col) = y[k];
  }
  return A;
}

TEST(NucleusStages, StagedStepMatchesNucleusStep) {
  const BoxBlockScene scene = make_box_block_scene(3e-3);
  Nucleus whole(scene.nucleus, scene.solver, scene.gravity, scene.statics);
  StagedNucleus staged(scene.nucleus, scene.solver, scene.gravity, scene.statics);
  Collider blade = scene.blade;
  blade.linear_velocity_m_s = Vec3(0.01, 0.0, -0.1);
  BodyReaction a, b;
  for (int s = 0; s < 30; ++s) {
    a.reference_point = b.reference_point = blade.pose.position;
    NumericalReport report;
    whole.step(kDt, {&blade, 1}, {&a, 1}, report);
    staged.step({&blade, 1}, {&b, 1});
    blade.pose.position += kDt * blade.linear_velocity_m_s;
  }
  ASSERT_EQ(whole.particle_count(), staged.state.x.size());
  for (std::size_t i = 0; i < whole.particle_count(); ++i) {
    ASSERT_EQ(whole.positions()[i], staged.state.x[i]) << i;
    ASSERT_EQ(whole.velocities()[i], staged.state.v[i]) << i;
  }
  EXPECT_EQ(a.force_N, b.force_N);
}

TEST(NucleusStages, SceneHasAwakeHaloWallsAndContacts) {
  PressedBlock s;
  s.n.up_to_assembly(s.moving());
  const NucleusWorkspace& w = s.n.work;
  EXPECT_GT(w.step.awake_end, 10u);
  EXPECT_GT(w.step.halo_end, w.step.awake_end);  // sleeping neighbours take part
  EXPECT_LT(w.step.awake_end, s.n.state.x.size());
  EXPECT_GT(w.walls.hit_count, 0u);
  EXPECT_GT(w.contacts.particles, 0u);
}

TEST(NucleusStages, OperatorIsTheSymmetricPositiveDefiniteMatrixItApplies) {
  PressedBlock s;
  s.n.up_to_assembly(s.moving());
  NucleusWorkspace& w = s.n.work;
  ASSERT_FALSE(w.step.frozen_moving);
  const std::size_t na = w.step.awake_end;
  const Eigen::MatrixXd A = dense_operator(w);
  const double scale = A.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  // Symmetric up to the single-precision pair records.
  EXPECT_LT((A - A.transpose()).cwiseAbs().maxCoeff(), 1e-6 * scale);
  // Positive definite (backward Euler's system; the PCG relies on it).
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (A + A.transpose()));
  EXPECT_EQ(llt.info(), Eigen::Success);
  // A generic vector: apply(x) == A x (linear: no term depends on x otherwise).
  std::vector<Vec3> x(w.step.outer_end, Vec3::Zero()), y(w.step.outer_end, Vec3::Zero());
  Eigen::VectorXd xv(3 * na);
  for (std::size_t k = 0; k < na; ++k) {
    x[k] = Vec3(std::sin(1.0 + k), std::cos(2.0 * k), 0.5 - std::sin(0.3 * k)) * 1e-3;
    xv.segment<3>(3 * k) = x[k];
  }
  apply_operator(w, w.apply, x.data(), y.data(), false);
  const Eigen::VectorXd Ax = A * xv;
  for (std::size_t k = 0; k < na; ++k)
    EXPECT_LT((y[k] - Vec3(Ax.segment<3>(3 * k))).norm(), 1e-5 * Ax.norm() / std::sqrt(na))
        << "row " << k;
  // The preconditioner's blocks are the inverses of the matrix's diagonal blocks.
  for (std::size_t k = 0; k < na; ++k) {
    const Sym3& d = w.sys.diag_inv[k];
    Eigen::Matrix3d inv;
    inv << d[0], d[3], d[4], d[3], d[1], d[5], d[4], d[5], d[2];
    const Eigen::Matrix3d block = A.block<3, 3>(3 * k, 3 * k);
    EXPECT_LT((inv * block - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-4)
        << "row " << k;
  }
}

// The contact shares of this step's solve that pull their particle toward the wall.
int pulling_contacts(const NucleusWorkspace& w) {
  int pulling = 0;
  std::size_t w0 = 0;
  while (w0 < w.walls.hit_count) {
    const std::int32_t k = w.walls.hits[w0].particle;
    std::size_t end = w0;
    while (end < w.walls.hit_count && w.walls.hits[end].particle == k) ++end;
    double share[kMaxWallHitsPerParticle] = {0, 0, 0, 0};
    pulling += contact_shares(w, k, w0, end, kDt, share);
    w0 = end;
  }
  return pulling;
}

// The pressed blade drawn back out faster than the block follows: held to the blade's normal
// velocity, the top layer would be pulled up by the contact. Those contacts let go, and the
// solve again from there leaves none pulling.
TEST(NucleusStages, AWithdrawnBladeLetsGoOfWhatItWouldPull) {
  PressedBlock s;
  s.blade.linear_velocity_m_s = Vec3(0.0, 0.0, 0.1);
  s.n.up_to_assembly(s.moving());
  NucleusWorkspace& w = s.n.work;
  NumericalReport report;
  solve_velocities(s.n.model, s.n.state, w, report);
  ASSERT_TRUE(report.ok);
  const int pulling = pulling_contacts(w);
  std::printf("  withdrawn blade: %d contacts pull after the first solve\n", pulling);
  ASSERT_GT(pulling, 0);
  EXPECT_EQ(release_pulling_contacts(w, kDt), pulling);
  std::size_t still_contact = 0;
  for (std::size_t h = 0; h < w.walls.hit_count; ++h) still_contact += w.walls.hits[h].contact;
  solve_velocities(s.n.model, s.n.state, w, report);
  ASSERT_TRUE(report.ok);
  std::printf("  after letting go: %zu contacts left, %d pull\n", still_contact,
              pulling_contacts(w));
  EXPECT_EQ(pulling_contacts(w), 0);
}

// The true residual of the solved velocities, |filtered (b - A v)|, filtered as the solve
// filters it, over the solve's scale (the right-hand side, floored at the weight impulse).
double true_relative_residual(NucleusWorkspace& w, const Vec3& gravity) {
  const std::size_t na = w.step.awake_end;
  std::vector<Vec3> v(w.pcg.v.begin(), w.pcg.v.end()), Av(v.size(), Vec3::Zero());
  apply_operator(w, w.apply, v.data(), Av.data(), w.step.frozen_moving);
  std::vector<Vec3> r(v.size(), Vec3::Zero());
  double b2 = 0.0, g2 = 0.0;
  for (std::size_t k = 0; k < na; ++k) {
    r[k] = w.sys.rhs[k] - Av[k];
    b2 += w.sys.rhs[k].squaredNorm();
    g2 += w.sys.mass[k] * w.sys.mass[k] * gravity.squaredNorm() * kDt * kDt;
  }
  filter(w.contacts, r);
  double r2 = 0.0;
  for (std::size_t k = 0; k < na; ++k) r2 += r[k].squaredNorm();
  return std::sqrt(r2) / std::sqrt(std::max(b2, g2));
}

// The block assembled with the instrument's motion, its velocities solved to 1e-6 (up to 1000
// iterations): the report of that solve.
NumericalReport solved_tightly(PressedBlock& s) {
  s.n.model.solver.tolerance = 1e-6;
  s.n.model.solver.max_iterations = 1000;
  s.n.up_to_assembly(s.moving());
  NumericalReport report;
  solve_velocities(s.n.model, s.n.state, s.n.work, report);
  return report;
}

TEST(NucleusStages, PcgResidualIsBelowTheTolerance) {
  PressedBlock s;
  const NumericalReport report = solved_tightly(s);
  NucleusWorkspace& w = s.n.work;
  ASSERT_TRUE(report.ok);
  EXPECT_GT(report.iterations, 0);
  EXPECT_LT(report.iterations, 1000);
  EXPECT_LE(report.residual, 1e-6);
  EXPECT_LE(true_relative_residual(w, s.n.model.gravity), 2e-6);
  // The solved velocities meet the contact constraints.
  const std::vector<Vec3> v(w.pcg.v.begin(), w.pcg.v.end());
  for (std::size_t c = 0; c < w.contacts.particles; ++c) {
    const std::int32_t k = w.contacts.particle[c];
    for (int a = 0; a < w.contacts.count[c]; ++a)
      EXPECT_NEAR(w.contacts.e[c][a].dot(v[k]), w.contacts.e[c][a].dot(w.contacts.v[c]), 1e-9);
  }
}

// A solve resumed after contacts let go starts from the residual it carries instead of a new
// product: its own residual must be the true one. The withdrawn blade's block, solved to 1e-6,
// its pulling contacts let go, solved again resumed: the true residual (a fresh product) is
// within twice the tolerance, as a solve from scratch is, and no contact pulls.
TEST(NucleusStages, AResumedSolveMeetsTheToleranceOnTheTrueResidual) {
  PressedBlock s;
  s.blade.linear_velocity_m_s = Vec3(0.0, 0.0, 0.1);
  ASSERT_TRUE(solved_tightly(s).ok);
  NucleusWorkspace& w = s.n.work;
  ASSERT_GT(release_pulling_contacts(w, kDt), 0);
  NumericalReport again;
  solve_velocities(s.n.model, s.n.state, w, again, /*resume=*/true);
  ASSERT_TRUE(again.ok);
  EXPECT_GT(again.iterations, 0);
  const double true_residual = true_relative_residual(w, s.n.model.gravity);
  std::printf("  resumed solve: %d iterations, its residual %.3g, the true one %.3g\n",
              again.iterations, again.residual, true_residual);
  EXPECT_LE(again.residual, 1e-6);
  EXPECT_LE(true_residual, 2e-6);
  EXPECT_EQ(pulling_contacts(w), 0);
}

// A particle sleeps after 40 ms of calm whatever its step (nucleus_sleep.cpp), so particles
// stepped every k-th 1 ms step (k ms at once) sleep after the same time: the block held still,
// every particle at rest and no instrument near, counted in steps of 1, 2, 3 and 4 ms.
TEST(NucleusStages, ACalmParticleSleepsAfterFortyMillisecondsWhateverItsStep) {
  const std::pair<double, int> cases[] = {{1e-3, 40}, {2e-3, 20}, {3e-3, 13}, {4e-3, 10}};
  for (const auto& [dt, expected] : cases) {
    BoxBlockScene scene = pressed_block_scene();
    StagedNucleus n{scene.nucleus, scene.solver, scene.gravity, scene.statics};
    for (std::size_t i = 0; i < n.state.x.size(); ++i) n.state.v[i] = Vec3::Zero();
    const std::size_t awake = n.state.active_count;
    ASSERT_GT(awake, 0u);
    update_verlet_grid(n.model, n.state, n.work.rows);
    int steps = 0;
    while (n.state.active_count == awake && steps < 1000) {
      wake_and_sleep(n.model, n.state, n.work, {}, dt);
      ++steps;
    }
    // The whole steps nearest to 40 ms (at 3 ms, 39 ms); then all of them at once.
    EXPECT_EQ(steps, expected) << "dt " << dt;
    EXPECT_EQ(n.state.active_count, 0u) << "dt " << dt;
  }
}

TEST(NucleusStages, AwakeListIsSortedAndMatchesTheFlags) {
  PressedBlock s;
  const NucleusModel& m = s.n.model;
  const NucleusState& st = s.n.state;
  begin_step(s.n.state, s.n.work, s.moving(), kDt);
  update_verlet_grid(m, s.n.state, s.n.work.rows);
  wake_and_sleep(m, s.n.state, s.n.work, s.moving(), kDt);
  std::vector<std::int32_t> listed(st.active.begin(), st.active.begin() + st.active_count);
  EXPECT_TRUE(std::is_sorted(listed.begin(), listed.end()));
  EXPECT_EQ(std::adjacent_find(listed.begin(), listed.end()), listed.end());  // no repeats
  std::size_t flagged = 0;
  for (std::size_t i = 0; i < st.x.size(); ++i) {
    flagged += st.awake[i];
    if (st.awake[i]) {
      EXPECT_FALSE(m.fixed[i]);
    }
    if (!st.awake[i]) {
      EXPECT_EQ(st.v[i], Vec3::Zero()) << "a sleeping particle moves: " << i;
    }
  }
  EXPECT_EQ(flagged, listed.size());
  for (const std::int32_t i : listed) {
    EXPECT_TRUE(st.awake[i]);
  }
  // Every particle near the blade is awake.
  for (std::size_t i = 0; i < st.x.size(); ++i) {
    if (signed_distance(s.blade, st.x[i], nullptr) < m.solver.sleep_distance_m) {
      EXPECT_TRUE(st.awake[i]) << i;
    }
  }
}

TEST(NucleusStages, PairsAreEveryNeighbourPairOnceWithinR) {
  PressedBlock s;
  s.n.up_to_assembly(s.moving());
  const NucleusModel& m = s.n.model;
  const NucleusState& st = s.n.state;
  const NucleusWorkspace& w = s.n.work;
  const PairList& pairs = w.pairs;
  ASSERT_FALSE(pairs.overflow);
  std::set<std::pair<std::int32_t, std::int32_t>> seen;
  auto check = [&](std::size_t p, bool near) {
    const std::int32_t li = pairs.i[p], lj = pairs.j[p];
    EXPECT_LT(li, lj);  // a row's pairs have a larger second end
    const std::int32_t i = w.step.global[li], j = w.step.global[lj];
    const Vec3 d = st.x[j] - st.x[i];
    EXPECT_NEAR(pairs.r[p], d.norm(), 1e-15);
    EXPECT_LT(pairs.r[p], m.radius);
    EXPECT_EQ(pairs.r[p] < m.density_radius, near);
    EXPECT_NEAR(pairs.n[p].dot(d), d.norm(), 1e-15);
    EXPECT_TRUE(seen.insert({std::min(i, j), std::max(i, j)}).second) << "pair twice";
  };
  for (std::size_t p = 0; p < pairs.near; ++p) check(p, true);
  for (std::size_t p = pairs.cap - pairs.far; p < pairs.cap; ++p) check(p, false);
  EXPECT_EQ(pairs.count, seen.size());
  // Complete: every pair within R with an awake or halo particle, by brute force; the halo
  // is exactly the sleeping particles within R of an awake one.
  const std::size_t n = st.x.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::int32_t li = w.step.local[i];
    const bool in_rows = li >= 0 && static_cast<std::size_t>(li) < w.step.halo_end;
    for (std::size_t j = i + 1; j < n; ++j) {
      const std::int32_t lj = w.step.local[j];
      const bool j_rows = lj >= 0 && static_cast<std::size_t>(lj) < w.step.halo_end;
      if (!in_rows && !j_rows) continue;
      if ((st.x[j] - st.x[i]).norm() >= m.radius) continue;
      const auto key = std::make_pair(static_cast<std::int32_t>(i), static_cast<std::int32_t>(j));
      EXPECT_EQ(seen.count(key), 1u) << "missing pair " << i << " " << j;
      if (st.awake[i]) {
        EXPECT_TRUE(j_rows);
      }
      if (st.awake[j]) {
        EXPECT_TRUE(in_rows);
      }
    }
  }
}

// While every particle is awake, rows leave their lower parts (the neighbours below them) for
// later: no step reads them then. When particles fall asleep inside the same grid build, the
// lower parts built then must give the same pairs, in the same order and with the same bits,
// as whole rows built with those particles asleep from the start.
TEST(NucleusStages, ALowerPartBuiltLaterGivesTheSamePairsAsAWholeRow) {
  const BoxBlockScene scene = make_box_block_scene(3e-3);
  StagedNucleus later(scene.nucleus, scene.solver, scene.gravity, scene.statics);
  StagedNucleus whole(scene.nucleus, scene.solver, scene.gravity, scene.statics);
  const std::size_t n = later.state.x.size();
  ASSERT_EQ(later.state.active_count, n);  // a fresh lattice: every particle awake
  auto pair_up = [](StagedNucleus& s) {
    begin_step(s.state, s.work, {}, kDt);
    update_verlet_grid(s.model, s.state, s.work.rows);
    build_pairs(s.model, s.state, s.work);
  };
  pair_up(later);
  std::size_t deferred = 0;
  for (std::size_t i = 0; i < n; ++i) deferred += later.work.rows.lower_at[i] < 0 ? 1 : 0;
  EXPECT_EQ(deferred, n);
  // Every third particle asleep, in both.
  for (NucleusState* st : {&later.state, &whole.state}) {
    st->active_count = 0;
    for (std::size_t i = 0; i < n; ++i) {
      st->awake[i] = i % 3 == 1 ? 0 : 1;
      if (st->awake[i]) st->active[st->active_count++] = static_cast<std::int32_t>(i);
    }
  }
  const std::uint32_t epoch = later.work.rows.epoch;
  pair_up(later);
  ASSERT_EQ(later.work.rows.epoch, epoch);  // nothing moved: the same grid build
  pair_up(whole);
  test::expect_same_pairs(later.work, whole.work);
}

TEST(NucleusStages, WallHitsAreGroupedByParticleAndWithinReach) {
  PressedBlock s;
  s.n.up_to_assembly(s.moving());
  const NucleusModel& m = s.n.model;
  const StepWalls& walls = s.n.work.walls;
  const double wall_range = m.radius + 0.5 * m.h;
  for (std::size_t h = 0; h < walls.hit_count; ++h) {
    const WallHit& hit = walls.hits[h];
    if (h > 0) {
      EXPECT_LE(walls.hits[h - 1].particle, hit.particle);
    }
    EXPECT_GE(walls.slot[hit.particle], 0);
    // Within the wall range, or a contact within its reach.
    if (hit.distance >= wall_range) {
      EXPECT_TRUE(hit.contact);
    }
    EXPECT_NEAR(hit.normal.norm(), 1.0, 1e-12);
  }
  // Hits per particle are bounded.
  std::size_t h = 0;
  while (h < walls.hit_count) {
    std::size_t e = h;
    while (e < walls.hit_count && walls.hits[e].particle == walls.hits[h].particle) ++e;
    EXPECT_LE(e - h, static_cast<std::size_t>(kMaxWallHitsPerParticle));
    h = e;
  }
}

TEST(NucleusStages, ProjectionKeepsAwakeParticlesOutsideTheSolids) {
  PressedBlock s;
  s.n.up_to_assembly(s.moving());
  NumericalReport report;
  s.reaction.reference_point = s.blade.pose.position;
  s.n.from_solve(s.moving(), s.reactions(), report);
  ASSERT_TRUE(report.ok);
  Collider blade_end = s.blade;
  blade_end.pose.position += kDt * s.blade.linear_velocity_m_s;
  const NucleusWorkspace& w = s.n.work;
  for (std::size_t k = 0; k < w.step.awake_end; ++k) {
    const Vec3& x = s.n.state.x[w.step.global[k]];
    for (const Collider& c : s.n.model.statics) EXPECT_GT(signed_distance(c, x, nullptr), 0.0);
    EXPECT_GT(signed_distance(blade_end, x, nullptr), 0.0);
  }
  EXPECT_GT(s.reaction.force_N.z(), 0.0);  // the block pushes the blade back up
}

TEST(NucleusStages, BondsBreakOnlyBeyondTheirLimit) {
  // The blade pushed deep and fast into a weak material: bonds break.
  MaterialConfig weak;
  weak.bond_break_m = 0.05e-3;
  BoxBlockScene scene = make_box_block_scene(3e-3, weak);
  scene.solver.sleep_enabled = false;
  StagedNucleus n(scene.nucleus, scene.solver, scene.gravity, scene.statics);
  Collider blade = scene.blade;
  blade.linear_velocity_m_s = Vec3(0.0, 0.0, -0.3);
  BodyReaction reaction;
  std::size_t broken = 0;
  for (int s = 0; s < 30; ++s) {
    const std::vector<std::uint8_t> alive_before = n.state.bond_alive;
    n.step({&blade, 1}, {&reaction, 1});
    blade.pose.position += kDt * blade.linear_velocity_m_s;
    const BondTable& bonds = n.model.bonds;
    for (std::size_t b = 0; b < bonds.size(); ++b) {
      const double r = (n.state.x[bonds.ij[2 * b + 1]] - n.state.x[bonds.ij[2 * b]]).norm();
      const double stretch = std::abs(r - bonds.rest[b]);
      if (alive_before[b] && !n.state.bond_alive[b]) {
        ++broken;
        EXPECT_GT(stretch, bonds.break_stretch[b] * (1.0 - 1e-12)) << "bond " << b;
      }
      // Every particle is awake, so every bond was tested: the intact ones are within limits.
      if (n.state.bond_alive[b]) {
        EXPECT_LE(stretch, bonds.break_stretch[b] * (1.0 + 1e-12));
      }
      if (!alive_before[b]) {
        EXPECT_FALSE(n.state.bond_alive[b]) << "a bond healed";
      }
    }
  }
  EXPECT_GT(broken, 0u);
  EXPECT_EQ(broken, n.state.broken_bonds);
}

}  // namespace
}  // namespace acdr::nucleus
