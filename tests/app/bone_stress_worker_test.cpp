// The bone's worker thread when the bone cannot be built: the samples handed to it are still
// taken (the stepping thread never blocks on it), and finish() reports why, without metrics.
// A live view's wish for every element's stress is met with the same metrics. (Its solved
// figures are compared with a re-score in bone_metrics_replay_test.cpp.)
#include "app/bone_stress_worker.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>

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

TEST(BoneStressWorker, AWantedFieldIsPublishedWithEveryElementAndTheSameMetrics) {
  const Anatomy anatomy(test::coarse_anatomy("none"));
  BoneModelConfig config;
  config.enabled = true;
  config.fem.meshing.size_m = 3.0e-3;  // coarse: a few seconds to mesh
  BoneLoadRecord sample;
  sample.t_s = 0.01;
  BoneLoadPoint& p = sample.points.emplace_back();
  p.point_m = Eigen::Vector3f(0.0f, static_cast<float>(anatomy.landmarks().c5_upper_endplate_y_m),
                              1e-3f);
  p.force_N = Eigen::Vector3f(0.0f, -5.0f, 0.0f);
  p.radius_m = 1.5e-3f;
  p.vertebra = 1;
  // The same sample through a worker asked for fields and one that is not.
  BoneStressSummary with_field, without;
  std::string error;
  // One meshing: the second worker loads the meshes from the first one's cache.
  const std::string cache = (std::filesystem::temp_directory_path() /
                             ("acdr_bone_worker_" + std::to_string(::getpid())))
                                .string();
  std::filesystem::remove_all(cache);
  {
    BoneStressWorker worker(anatomy, config, cache);
    worker.set_field_wanted(true);
    worker.push(sample);  // alone in the queue: the worker has caught up when it solves it
    ASSERT_TRUE(worker.finish(&with_field, nullptr, &error)) << error;
    ASSERT_NE(worker.bone(), nullptr);
    EXPECT_EQ(worker.latest_field().version(), 1u);
    worker.latest_field().read([&](const BoneStressField& f) {
      EXPECT_TRUE(f.element_von_mises_Pa[0].empty());  // C4 not loaded
      EXPECT_EQ(f.element_von_mises_Pa[1].size(), worker.bone()->vertebra(1).mesh().tets.size());
      for (float s : f.element_von_mises_Pa[1]) EXPECT_FALSE(std::isnan(s));
      EXPECT_EQ(f.loads.size(), 1u);
      EXPECT_DOUBLE_EQ(f.result.t_s, 0.01);
    });
  }
  {
    BoneStressWorker worker(anatomy, config, cache);
    worker.push(sample);
    ASSERT_TRUE(worker.finish(&without, nullptr, &error)) << error;
    EXPECT_EQ(worker.latest_field().version(), 0u);
  }
  std::filesystem::remove_all(cache);
  EXPECT_EQ(with_field.peak_Pa, without.peak_Pa);
}

}  // namespace
}  // namespace acdr
