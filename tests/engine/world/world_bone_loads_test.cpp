// The loads the world samples for the bone's finite-element model: at the configured period,
// the instrument's contact points on the vertebra it touches (adding up to the contact force
// on the instrument, opposite), the nucleus's reaction gathered per cell, no allocation added
// to the step, and the physics unchanged by the sampling (same state hash with it off).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "engine/world/world.hpp"
#include "tests/engine/anatomy/coarse_segment_scene.hpp"
#include "tests/support/counting_allocator.hpp"

namespace acdr {
namespace {

class WorldBoneLoads : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = (std::filesystem::temp_directory_path() /
            ("acdr_world_bone_loads_" + std::string(info->name()) + "_" + std::to_string(::getpid())))
               .string();
    std::filesystem::remove_all(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string dir_;
};

TEST_F(WorldBoneLoads, SampledAtThePeriodFromInstrumentAndNucleusWithoutChangingPhysics) {
  WorldConfig sampled = test::coarse_segment_world(dir_);
  sampled.anatomy.bone_load_period_s = 0.01;  // every 10 steps at 1 ms
  WorldConfig plain = sampled;
  plain.anatomy.bone_load_period_s = 0.0;
  World world(sampled);
  World reference(plain);
  DeviceSample s;
  s.pose = test::coarse_segment_push(sampled);
  int samples = 0, with_instrument = 0, with_nucleus = 0;
  long allocations = 0, reference_allocations = 0;
  double worst_balance = 0.0;
  for (int i = 0; i < 400; ++i) {
    s.t_s = world.time_s();
    const Frame* frame = nullptr;
    allocations += test_support::allocations_during([&] { frame = &world.step(s); });
    reference_allocations += test_support::allocations_during([&] { reference.step(s); });
    const BoneLoadSample* loads = world.bone_loads();
    EXPECT_EQ(loads != nullptr, world.step_count() % 10 == 0) << world.step_count();
    EXPECT_EQ(reference.bone_loads(), nullptr);
    if (!loads) continue;
    ++samples;
    EXPECT_DOUBLE_EQ(loads->t_s, world.time_s());
    EXPECT_EQ(loads->dropped, 0);
    Vec3 instrument = Vec3::Zero();
    bool any_instrument = false, any_nucleus = false;
    for (int k = 0; k < loads->count; ++k) {
      const BoneLoadPoint& p = loads->points[k];
      ASSERT_LE(p.vertebra, 1);
      if (p.source == BoneLoadSource::kInstrument) {
        any_instrument = true;
        instrument += p.force_N.cast<double>();
        // The cup is pushed onto C5.
        EXPECT_EQ(p.vertebra, 1);
      } else {
        any_nucleus = true;
        EXPECT_GT(p.radius_m, 0.0f);
      }
    }
    with_instrument += any_instrument;
    with_nucleus += any_nucleus;
    // The bone feels the opposite of the rigid contact force on the instrument (only bone is
    // near the cup: no box, no ground in this scene), to single precision.
    const double scale = std::max(1e-3, frame->contact_force_N.norm());
    worst_balance = std::max(worst_balance, (instrument + frame->contact_force_N).norm() / scale);
  }
  EXPECT_EQ(samples, 40);
  EXPECT_GT(with_instrument, 5);  // the cup reached the endplate
  EXPECT_GT(with_nucleus, 5);     // and the particles press on the bone
  EXPECT_LT(worst_balance, 1e-5);
  // Sampling allocates nothing: the step allocates exactly what it does without it (Bullet
  // may allocate a contact manifold the first time the cup meets a vertebra).
  EXPECT_EQ(allocations, reference_allocations) << "heap allocations by the bone load sampling";
  EXPECT_LE(reference_allocations, 4);
  // Sampling reads the state only: the physics is the same bit for bit.
  EXPECT_EQ(world.state_hash(), reference.state_hash());
  EXPECT_FALSE(world.failed());
}

}  // namespace
}  // namespace acdr
