// The bone's worker thread when the bone cannot be built: the samples handed to it are still
// taken (the stepping thread never blocks on it), and finish() reports why, without metrics.
// (Its solved figures are compared with a re-score in bone_metrics_replay_test.cpp.)
#include "app/bone_stress_worker.hpp"

#include <gtest/gtest.h>

#include "tests/engine/anatomy/coarse_segment_scene.hpp"

namespace acdr {
namespace {

TEST(BoneStressWorker, ABoneThatCannotBeBuiltIsReportedAndItsSamplesDrained) {
  const Anatomy anatomy(test::coarse_anatomy("none"));
  BoneModelConfig config;
  config.enabled = true;
  config.fem.materials.cancellous.poisson_ratio = 0.7;  // not a material
  BoneStressWorker worker(anatomy, config, "");
  BoneLoadRecord sample;
  sample.t_s = 0.01;
  sample.points.emplace_back();
  for (int i = 0; i < 50; ++i) worker.push(sample);
  BoneStressSummary summary;
  BoneWorkerStats stats;
  std::string error;
  EXPECT_FALSE(worker.finish(&summary, &stats, &error));
  EXPECT_NE(error.find("poisson"), std::string::npos) << error;
  EXPECT_EQ(stats.samples, 0);
  EXPECT_EQ(summary.samples, 0);
}

}  // namespace
}  // namespace acdr
