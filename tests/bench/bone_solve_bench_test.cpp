// The bone's solve timing for `acdr bench`: percentiles, and the figures of a few samples
// solved on a coarse segment (what was solved is counted; times are positive, never checked
// against a figure: tests do not time).
#include "bench/bone_solve_bench.hpp"

#include <gtest/gtest.h>

#include "tests/engine/anatomy/coarse_segment_scene.hpp"

namespace acdr {
namespace {

TEST(BoneSolveBench, SummaryTakesMedianMeanP95AndMax) {
  std::vector<double> ms;
  for (int i = 20; i >= 1; --i) ms.push_back(i);  // 1 .. 20, unsorted
  const TimingSummary s = summarize_ms(ms);
  EXPECT_DOUBLE_EQ(s.median_ms, 11.0);
  EXPECT_DOUBLE_EQ(s.mean_ms, 10.5);
  EXPECT_DOUBLE_EQ(s.p95_ms, 19.0);
  EXPECT_DOUBLE_EQ(s.max_ms, 20.0);
  const TimingSummary none = summarize_ms({});
  EXPECT_EQ(none.max_ms, 0.0);
}

TEST(BoneSolveBench, CountsTheSolvesOfEachLoadedVertebra) {
  const Anatomy anatomy(test::coarse_anatomy("none"));
  BoneModelConfig config;
  config.enabled = true;
  config.fem.meshing.size_m = 3.0e-3;
  std::string error;
  auto bone = BoneSegment::build(anatomy, config, "", &error);
  ASSERT_NE(bone, nullptr) << error;
  BoneLoadPoint c5;
  c5.point_m = Eigen::Vector3f(0.0f, static_cast<float>(anatomy.landmarks().c5_upper_endplate_y_m),
                               1e-3f);
  c5.force_N = Eigen::Vector3f(0.0f, -5.0f, 0.0f);
  c5.vertebra = 1;
  BoneLoadPoint c4 = c5;
  c4.point_m.y() = static_cast<float>(anatomy.landmarks().c4_lower_endplate_y_m);
  c4.force_N = -c5.force_N;
  c4.vertebra = 0;
  // Three samples: C5 alone, both, none.
  const std::vector<BoneLoadRecord> samples = {{0.01, {c5}}, {0.02, {c5, c4}}, {0.03, {}}};
  const BoneSolveFigures f = time_bone_solves(*bone, samples, 2);
  EXPECT_TRUE(f.measured);
  EXPECT_EQ(f.samples, 3u);
  EXPECT_EQ(f.solves, 3u);
  EXPECT_DOUBLE_EQ(f.mean_loads_per_solve, 1.0);
  EXPECT_GT(f.solve_cpu.median_ms, 0.0);
  EXPECT_GE(f.solve_cpu.max_ms, f.solve_cpu.median_ms);
  EXPECT_GT(f.sample_wall.max_ms, 0.0);
  EXPECT_GT(f.back_substitution_share[1], 0.0);
  EXPECT_LT(f.back_substitution_share[1], 1.0);
  EXPECT_EQ(f.free_dofs[1], bone->vertebra(1).model().report().free_dofs);
}

}  // namespace
}  // namespace acdr
