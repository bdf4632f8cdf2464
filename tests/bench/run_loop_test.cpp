// The benchmark runs' shared stepping loop on synthetic steps (no physics): step count, force
// windows, the instrument path at window ends, the lead before the window, stopping, warm-up
// and progress. No timing
// assertions beyond "measured at all".
#include "bench/run_loop.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace acdr {
namespace {

RunWindow window_of(double sample_s, int warmup_steps = 0) {
  RunWindow w;
  w.sample_s = sample_s;
  w.warmup_steps = warmup_steps;
  return w;
}

TEST(RunLoop, StepCountIsTheRoundedDurationOverTheStep) {
  EXPECT_EQ(run_step_count(0.1, 1e-3), 100);
  EXPECT_EQ(run_step_count(0.1, 0.3e-3), 333);
  EXPECT_EQ(run_step_count(0.0, 1e-3), 0);
}

TEST(RunLoop, AveragesTheForceOverEachWindowAndKeepsThePoseAtItsEnd) {
  // 30 steps of 1 ms in 10 ms windows; step k pushes k N along x: window j averages
  // 10 j .. 10 j + 9, i.e. 10 j + 4.5 N.
  RunTrace out;
  std::vector<std::int64_t> seen;
  const std::int64_t ran = run_timed_loop(0.03, 1e-3, window_of(0.01), out, [&](std::int64_t k) {
    seen.push_back(k);
    LoopStep s;
    s.force_N = Vec3(double(k), 0, 0);
    s.instrument = Pose{Vec3(0, 0, double(k + 1)), Quat::Identity()};
    return s;
  });
  EXPECT_EQ(ran, 30);
  ASSERT_EQ(seen.size(), 30u);
  EXPECT_EQ(seen.front(), 0);
  EXPECT_EQ(seen.back(), 29);
  ASSERT_EQ(out.t_s.size(), 3u);
  ASSERT_EQ(out.instrument.size(), 3u);
  for (int j = 0; j < 3; ++j) {
    EXPECT_NEAR(out.t_s[j], 0.01 * (j + 1), 1e-15);
    EXPECT_NEAR(out.force_N[j].x(), 10.0 * j + 4.5, 1e-12);
    EXPECT_EQ(out.instrument[j].position.z(), 10.0 * (j + 1));  // the pose after step 10 j + 9
  }
  EXPECT_EQ(out.timed_steps, 30);
  EXPECT_GE(out.wall_s, 0.0);
  EXPECT_GE(out.max_step_wall_s, 0.0);
}

TEST(RunLoop, WindowsCloseOnTheirBoundaryAtAStepThatDoesNotDivideThem) {
  // 3 ms steps in 10 ms windows: a window closes at the first step ending at or past its
  // boundary (steps ending at 12, 21, 30 ms), only whole windows of the duration count.
  RunTrace out;
  run_timed_loop(0.03, 3e-3, window_of(0.01), out, [](std::int64_t) {
    LoopStep s;
    s.force_N = Vec3(1, 2, 3);
    return s;
  });
  ASSERT_EQ(out.t_s.size(), 3u);
  EXPECT_TRUE(out.instrument.empty());  // the steps gave no pose
  for (const Vec3& f : out.force_N) EXPECT_EQ(f, Vec3(1, 2, 3));
}

TEST(RunLoop, AStepThatSaysStopEndsTheRun) {
  RunTrace out;
  const std::int64_t ran = run_timed_loop(0.1, 1e-3, window_of(0.01), out, [](std::int64_t k) {
    LoopStep s;
    s.stop = k == 14;
    return s;
  });
  EXPECT_EQ(ran, 15);
  EXPECT_EQ(out.t_s.size(), 1u);  // the first window closed at step 9; the second never did
  EXPECT_EQ(out.timed_steps, 15);
}

TEST(RunLoop, WarmUpStepsAreNotTimedAndProgressEndsAtOne) {
  RunTrace out;
  std::vector<double> progress;
  run_timed_loop(
      0.6, 1e-3, window_of(0.01, 5), out, [](std::int64_t) { return LoopStep{}; },
      [&](double f) { progress.push_back(f); });
  EXPECT_EQ(out.timed_steps, 595);
  // Every 250 steps from the first, then the end.
  ASSERT_EQ(progress.size(), 4u);
  EXPECT_EQ(progress[0], 0.0);
  EXPECT_NEAR(progress[1], 250.0 / 600.0, 1e-15);
  EXPECT_NEAR(progress[2], 500.0 / 600.0, 1e-15);
  EXPECT_EQ(progress[3], 1.0);
}

TEST(RunLoop, TheLeadRunsFirstAndIsNeitherComparedNorTimedButItsPosesAreKept) {
  // 20 ms of lead, then 30 ms of window, 1 ms steps in 10 ms windows: 50 steps in all; the
  // force windows hold only the window's steps (k = 20 ... 49), the poses every boundary from
  // the run's start (5 of them).
  RunWindow w = window_of(0.01);
  w.lead_s = 0.02;
  EXPECT_EQ(lead_step_count(w, 1e-3), 20);
  EXPECT_EQ(lead_step_count(w, 2e-3), 10);
  w.start_s = 1.0;
  EXPECT_NEAR(run_start_s(w, 1e-3), 0.98, 1e-15);
  RunTrace out;
  std::vector<double> progress;
  std::int64_t last = -1;
  const std::int64_t ran = run_timed_loop(
      0.03, 1e-3, w, out,
      [&](std::int64_t k) {
        last = k;
        LoopStep s;
        s.force_N = Vec3(double(k), 0, 0);
        s.instrument = Pose{Vec3(0, 0, double(k + 1)), Quat::Identity()};
        return s;
      },
      [&](double f) { progress.push_back(f); });
  EXPECT_EQ(ran, 30);  // the window's steps
  EXPECT_EQ(last, 49);
  EXPECT_EQ(out.timed_steps, 30);
  ASSERT_EQ(out.t_s.size(), 3u);
  for (int j = 0; j < 3; ++j) {
    EXPECT_NEAR(out.t_s[j], 0.01 * (j + 1), 1e-15);  // from the window's start
    EXPECT_NEAR(out.force_N[j].x(), 20.0 + 10.0 * j + 4.5, 1e-12);
  }
  ASSERT_EQ(out.instrument.size(), 5u);
  for (int j = 0; j < 5; ++j) EXPECT_EQ(out.instrument[j].position.z(), 10.0 * (j + 1));
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress.back(), 1.0);
}

TEST(RunLoop, NearestRankPercentileIsTheSmallestValueAtOrAboveTheFraction) {
  std::vector<double> none;
  EXPECT_EQ(nearest_rank_percentile(none, 0.99), 0.0);
  // 100 steps, two slow: the 99th percentile is the first of them; one slow: a fast one.
  std::vector<double> v(100, 1.0);
  v[17] = 5.0;
  v[60] = 7.0;
  EXPECT_EQ(nearest_rank_percentile(v, 0.99), 5.0);
  std::vector<double> w(100, 1.0);
  w[3] = 9.0;
  EXPECT_EQ(nearest_rank_percentile(w, 0.99), 1.0);
  std::vector<double> one{4.0};
  EXPECT_EQ(nearest_rank_percentile(one, 0.99), 4.0);
  std::vector<double> u{3.0, 1.0, 2.0};
  EXPECT_EQ(nearest_rank_percentile(u, 0.5), 2.0);
}

}  // namespace
}  // namespace acdr
