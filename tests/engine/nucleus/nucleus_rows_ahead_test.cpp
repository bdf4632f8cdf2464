// Rows built ahead (nucleus_rows_ahead.cpp): begun from a copy of the state, built in shares
// and adopted a particle step later, they are the rows a rebuild at the copy's positions
// makes, so the step that adopts them pairs exactly as a step whose grid was rebuilt there;
// a grid that no longer holds at the adopting positions is dropped and the step rebuilds it.
#include <cmath>
#include <cstdint>

#include <gtest/gtest.h>

#include "engine/nucleus/nucleus_stages.hpp"
#include "tests/engine/nucleus/same_pairs.hpp"
#include "verification/box_block_scene.hpp"

namespace acdr::nucleus {
namespace {

constexpr double kDt = 1e-3;

struct Staged {
  NucleusModel model;
  NucleusState state;
  NucleusWorkspace work;

  explicit Staged(const BoxBlockScene& scene) {
    model.config = scene.nucleus;
    model.solver = scene.solver;
    model.gravity = scene.gravity;
    const NucleusParticleSetup setup = lattice_setup(scene.nucleus, {}, scene.statics);
    build_model(model, scene.statics, setup);
    init_state(model, setup, state);
    reserve_workspace(model, work);
    reserve_rows_ahead(model, work);
  }
  void pair_up() {
    begin_step(state, work, {}, kDt);
    update_verlet_grid(model, state, work.rows);
    build_pairs(model, state, work);
  }
  // Every third particle asleep; the awake ones moved by `scale` times a fixed pattern that
  // makes particles 0 and 1 the two farthest moved (each scale * skin / 2).
  void sleep_every_third() {
    state.active_count = 0;
    for (std::size_t i = 0; i < state.x.size(); ++i) {
      state.awake[i] = i % 3 == 2 ? 0 : 1;
      if (state.awake[i]) state.active[state.active_count++] = static_cast<std::int32_t>(i);
    }
  }
  void move_awake(double scale, int seed) {
    for (std::size_t i = 0; i < state.x.size(); ++i) {
      if (!state.awake[i]) continue;
      const double f = i < 2 ? 0.5 : 0.2 * std::sin(double(i * 7 + seed));
      state.x[i] += scale * model.skin * f * Vec3(0.6, -0.48, 0.64);  // a unit direction
    }
  }
};

TEST(NucleusRowsAhead, AdoptedRowsPairAsARebuildAtTheirPositions) {
  const BoxBlockScene scene = make_box_block_scene(3e-3);
  Staged ahead(scene), rebuilt(scene);
  for (Staged* s : {&ahead, &rebuilt}) {
    s->sleep_every_third();
    s->pair_up();  // the first grid
    s->move_awake(0.9, 1);  // bound 0.9 skin: the next step is the last this grid serves
  }
  // Begun from these positions and built in two shares (a step runs in between).
  ASSERT_TRUE(begin_rows_ahead(ahead.model, ahead.state, ahead.work));
  build_rows_ahead(ahead.model, ahead.work.ahead, 0.5);
  EXPECT_GT(ahead.work.ahead.built, 0u);
  EXPECT_LT(ahead.work.ahead.built, ahead.state.active_count);
  // The other: its grid rebuilt in place at the same positions.
  rebuilt.work.rows.grid_valid = false;
  update_verlet_grid(rebuilt.model, rebuilt.state, rebuilt.work.rows);
  ahead.pair_up();  // the step in flight, on the old grid
  build_rows_ahead(ahead.model, ahead.work.ahead, 1.0);
  // Both move on, less than a skin from the copy, and the next step pairs.
  for (Staged* s : {&ahead, &rebuilt}) s->move_awake(0.5, 2);
  const std::size_t builds = ahead.work.rows.grid_builds;
  ASSERT_TRUE(adopt_rows_ahead(ahead.model, ahead.state, ahead.work));
  EXPECT_EQ(ahead.work.rows.grid_builds, builds + 1);
  ahead.pair_up();
  EXPECT_EQ(ahead.work.rows.grid_builds, builds + 1) << "the adopted grid was rebuilt again";
  rebuilt.pair_up();
  test::expect_same_pairs(ahead.work, rebuilt.work);
}

TEST(NucleusRowsAhead, AGridThatNoLongerHoldsIsDroppedAndTheStepRebuilds) {
  const BoxBlockScene scene = make_box_block_scene(3e-3);
  Staged s(scene);
  s.sleep_every_third();
  s.pair_up();
  // Far from a skin moved, slowly: nothing is begun.
  s.move_awake(0.1, 1);
  EXPECT_FALSE(begin_rows_ahead(s.model, s.state, s.work));
  s.move_awake(0.1, 2);
  EXPECT_FALSE(begin_rows_ahead(s.model, s.state, s.work));
  // Fast enough that the next step would be one too late.
  s.move_awake(0.5, 3);
  ASSERT_TRUE(begin_rows_ahead(s.model, s.state, s.work));
  // Then particle 0 flies off by two skins before the adopting launch.
  s.state.x[0] += 2.0 * s.model.skin * Vec3::UnitX();
  const std::size_t builds = s.work.rows.grid_builds;
  EXPECT_FALSE(adopt_rows_ahead(s.model, s.state, s.work));
  EXPECT_EQ(s.work.ahead.adopted, 0u);
  s.pair_up();
  EXPECT_EQ(s.work.rows.grid_builds, builds + 1) << "the step rebuilt its grid";
}

}  // namespace
}  // namespace acdr::nucleus
