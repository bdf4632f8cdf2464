// No heap allocation inside World::step (docs/architecture.md, The step): the shared counting
// allocator (tests/support), and a scoop through the nucleus that exercises waking, sleeping,
// neighbour-row rebuilds, bond breaks and wall contact. Allocations before the counted steps (building the
// world, Bullet's first contact manifolds) are allowed; none after.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "engine/world/world.hpp"
#include "tests/support/counting_allocator.hpp"

namespace acdr {
namespace {

/// A small box (10 x 10 mm cavity, 5 mm of nucleus at 1 mm spacing) and a prism blade.
WorldConfig small_box() {
  WorldConfig c;
  c.ground.enabled = true;
  c.ground.height_m = -2e-3;
  c.box.enabled = true;
  c.box.inner_min_m = Vec3(-5e-3, -5e-3, 0);
  c.box.inner_max_m = Vec3(5e-3, 5e-3, 8e-3);
  c.nucleus.enabled = true;
  c.nucleus.spacing_m = 1e-3;
  c.nucleus.materials.push_back(MaterialConfig{});
  c.nucleus.blocks.push_back({Vec3(-5e-3, -5e-3, 0), Vec3(5e-3, 5e-3, 5e-3), 0});
  c.instrument.enabled = true;
  c.instrument.blade_size_m = Vec3(4e-3, 4e-3, 1e-3);
  c.instrument.shaft_length_m = 0.05;
  c.instrument_start.position = Vec3(-2e-3, 0, 0.057);
  c.removal.min_m = Vec3(-5e-3, -5e-3, -1e-3);
  c.removal.max_m = Vec3(5e-3, 5e-3, 8e-3);
  return c;
}

/// A sample holding the instrument at `at` (asking for `instrument`), after 60 steps there:
/// the world settles and Bullet builds its contact state (allocations allowed).
DeviceSample settle(World& w, const Vec3& at, int instrument = -1) {
  DeviceSample s;
  s.pose.position = at;
  s.instrument = instrument;
  for (int i = 0; i < 60; ++i) w.step(s);
  return s;
}

// The particles at every step, every second step (multi-rate: the step between builds the
// rows the next one would rebuild), and every third step pipelined on the worker thread (a
// pipelined run's allocations, the worker's included, are counted as the stepping thread's;
// its neighbour rebuilds made ahead between the steps).
TEST(WorldAllocation, StepAllocatesNothing) {
  struct Rate {
    int every;
    bool pipelined;
  };
  for (const Rate rate : {Rate{1, false}, Rate{2, false}, Rate{3, true}}) {
    const int every = rate.every;
    WorldConfig c = small_box();
    c.solver.nucleus_every = every;
    c.solver.nucleus_pipelined = rate.pipelined;
    World w(c);
    DeviceSample s = settle(w, Vec3(-2e-3, 0, 0.057));
    const long before = test_support::heap_allocations();
    // Down into the material, then a drag along x and up out of it.
    for (int i = 0; i < 600; ++i) {
      const double t = i * 1e-3;
      if (t < 0.2) s.pose.position.z() -= 1.5e-5;
      else if (t < 0.45) s.pose.position.x() += 1.6e-5;
      else s.pose.position.z() += 2e-5;
      w.step(s);
    }
    const long during = test_support::heap_allocations() - before;
    ASSERT_FALSE(w.failed()) << every;
    // The scoop did exercise the nucleus: the blade met the material.
    EXPECT_GT(w.last_frame().active_particles, 0) << every;
    EXPECT_EQ(during, 0) << "heap allocations inside World::step, particles every " << every
                         << (rate.pipelined ? ", pipelined" : "");
    // Pipelined, the neighbour rebuilds were made ahead (a copy, a grid, rows, an adoption).
    if (rate.pipelined) {
      EXPECT_GT(w.nucleus()->rows_ahead_adopted(), 0u);
    }
  }
}

// A rongeur's bite: the jaws close on the gel (particles taken out of the solve), lift it out
// (bonds torn, the neighbour rows rebuilt as the bite leaves) and open (the particles given
// back): nothing allocated either.
TEST(WorldAllocation, RongeurBiteAllocatesNothing) {
  WorldConfig c = small_box();
  c.instrument.shape = InstrumentShape::kRongeur;
  c.instrument.jaw_length_m = 6e-3;
  c.instrument_start.position = Vec3(0, 0, 0.07);
  World w(c);
  DeviceSample s = settle(w, Vec3(0, 0, 0.07));
  const long before = test_support::heap_allocations();
  for (int i = 0; i < 1200; ++i) {
    const double t = i * 1e-3;
    if (t < 0.3) s.pose.position.z() -= 4.4e-5;        // down, jaws open
    else if (t < 0.6) s.grip = 1.0;                    // close
    else if (t < 0.9) s.pose.position.z() += 5e-5;     // lift the bite
    else s.grip = 0.0;                                 // open
    w.step(s);
  }
  const long during = test_support::heap_allocations() - before;
  ASSERT_FALSE(w.failed());
  EXPECT_TRUE(w.held_particles().empty());
  EXPECT_GT(w.last_frame().removed_target, 0);
  EXPECT_EQ(during, 0) << "heap allocations inside World::step";
}

// An exchange within the attempt: the blade scoops, goes out, the hand takes the rongeur, which
// bites, opens outside the disc (the shed load slides off) and gives the blade back. The
// shapes were built with the world, and the events name the instruments in full (names longer
// than a string keeps in place): the exchanges allocate nothing.
TEST(WorldAllocation, InstrumentExchangeAllocatesNothing) {
  WorldConfig c = small_box();
  InstrumentConfig blade = c.instrument;
  blade.name = "cup curette, 3 mm";
  InstrumentConfig rongeur = c.instrument;
  rongeur.name = "straight pituitary rongeur";
  rongeur.shape = InstrumentShape::kRongeur;
  rongeur.jaw_length_m = 6e-3;
  c.instruments = {blade, rongeur};
  c.instrument_start.position = Vec3(0, 0, 0.07);
  World w(c);
  DeviceSample s = settle(w, Vec3(0, 0, 0.07), 0);
  const long before = test_support::heap_allocations();
  for (int i = 0; i < 2400; ++i) {
    const double t = i * 1e-3;
    if (t < 0.3) s.pose.position.z() -= 4.0e-5;          // the blade into the gel
    else if (t < 0.6) s.pose.position.z() += 4.0e-5;     // and out
    else if (t < 0.7) s.instrument = 1;                  // the rongeur
    else if (t < 1.0) s.pose.position.z() -= 4.4e-5;     // down, jaws open
    else if (t < 1.3) s.grip = 1.0;                      // close
    else if (t < 1.6) s.pose.position.z() += 5e-5;       // lift the bite
    else if (t < 2.0) s.grip = 0.0;                      // open: it falls off
    else s.instrument = 0;                               // the blade again
    w.step(s);
  }
  const long during = test_support::heap_allocations() - before;
  ASSERT_FALSE(w.failed());
  std::vector<Event> events;
  w.drain_events(events);
  std::vector<std::string> exchanges;
  for (const Event& e : events)
    if (e.kind == EventKind::kInstrumentExchange) exchanges.push_back(e.detail);
  EXPECT_EQ(exchanges, (std::vector<std::string>{"straight pituitary rongeur",
                                                 "cup curette, 3 mm"}));  // there and back
  EXPECT_EQ(w.instrument_index(), 0);
  EXPECT_GT(w.last_frame().removed_target, 0);
  EXPECT_EQ(during, 0) << "heap allocations inside World::step";
}

// The device goes silent, comes back, then jumps: the events' texts ("device silent: force
// zeroed", "pose jump") are copied into slots made at build, not allocated.
TEST(WorldAllocation, EventsAllocateNothing) {
  World w(small_box());
  DeviceSample s = settle(w, Vec3(-2e-3, 0, 0.057));
  const long before = test_support::heap_allocations();
  for (int i = 0; i < 300; ++i) {
    s.stale = i >= 50 && i < 100;
    s.silence_s = s.stale ? (i - 49) * 1e-3 : 0.0;
    if (i == 200) s.pose.position.x() += 0.05;  // a 50 mm jump for one sample: rejected
    if (i == 201) s.pose.position.x() -= 0.05;
    w.step(s);
  }
  const long during = test_support::heap_allocations() - before;
  std::vector<Event> events;
  w.drain_events(events);
  std::vector<std::string> texts;
  for (const Event& e : events) texts.push_back(e.detail);
  EXPECT_EQ(texts, (std::vector<std::string>{"device silent: force zeroed", "pose jump"}));
  EXPECT_EQ(during, 0) << "heap allocations inside World::step";
}

}  // namespace
}  // namespace acdr
