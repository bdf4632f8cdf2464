// Benchmark runs' path helpers: the pose on a recorded path and the motion that follows it.
#include "bench/scene_run.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace acdr {
namespace {

/// A path sampled every 10 ms: moving at 0.1 m/s along x and turning at 2 rad/s about z.
std::vector<Pose> straight_turning_path(int samples) {
  std::vector<Pose> path;
  for (int k = 1; k <= samples; ++k) {
    const double t = 0.01 * k;
    path.push_back(Pose{Vec3(0.1 * t, 0, 0), Quat(Eigen::AngleAxisd(2.0 * t, Vec3::UnitZ()))});
  }
  return path;
}

TEST(SceneRun, PoseOnPathInterpolatesBetweenSamplesAndHoldsTheLast) {
  const std::vector<Pose> path = straight_turning_path(5);
  const Pose start;
  EXPECT_NEAR(pose_on_path(start, path, 0.01, 0.0).position.x(), 0.0, 1e-15);
  EXPECT_NEAR(pose_on_path(start, path, 0.01, 0.015).position.x(), 0.0015, 1e-15);
  EXPECT_NEAR(pose_on_path(start, path, 0.01, 1.0).position.x(), 0.005, 1e-15);
}

TEST(SceneRun, MotionOnPathGivesTheVelocitiesThatReachTheNextPose) {
  const std::vector<Pose> path = straight_turning_path(5);
  const double dt = 1e-3;
  const PathMotion m = motion_on_path(Pose{}, path, 0.01, 0.012, dt);
  EXPECT_NEAR(m.pose.position.x(), 0.0012, 1e-15);
  EXPECT_NEAR((m.velocity_m_s - Vec3(0.1, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((m.angular_velocity_rad_s - Vec3(0, 0, 2.0)).norm(), 0.0, 1e-9);
  // Past the path's end it holds still.
  const PathMotion end = motion_on_path(Pose{}, path, 0.01, 0.2, dt);
  EXPECT_EQ(end.velocity_m_s, Vec3::Zero());
  EXPECT_NEAR(end.angular_velocity_rad_s.norm(), 0.0, 1e-12);
}

TEST(SceneRun, SettingsOverrideTheScenesSleepOnlyWhenGiven) {
  WorldConfig scene;
  scene.solver.sleep_distance_m = 1.5e-3;
  scene.solver.sleep_speed_m_s = 3e-4;
  RunSettings keep;
  const WorldConfig kept = apply_settings(scene, keep);
  EXPECT_EQ(kept.solver.sleep_distance_m, 1.5e-3);
  EXPECT_EQ(kept.solver.sleep_speed_m_s, 3e-4);
  // The bench's reference: no nearer wake and no faster sleep than the engine's defaults.
  RunSettings reference;
  reference.sleep_distance_m = 6e-3;
  reference.sleep_speed_m_s = 1e-4;
  const WorldConfig ref = apply_settings(scene, reference);
  EXPECT_EQ(ref.solver.sleep_distance_m, 6e-3);
  EXPECT_EQ(ref.solver.sleep_speed_m_s, 1e-4);
}

}  // namespace
}  // namespace acdr
