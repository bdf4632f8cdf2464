// Tests of ui/trainee_view: under a display (xvfb-run), the window opens, the attempt runs on
// the haptic thread while the window watches it, the score screen follows, and the window's
// pictures show the scene, the HUD and the score. Skipped without one.
#include "ui/trainee_view.hpp"

#include <gtest/gtest.h>

#include "app/live_attempt.hpp"
#include "engine/devices/trajectory.hpp"
#include "scenarios/scenario_loader.hpp"
#include "tests/app/test_scenes.hpp"
#include "tests/db/db_test_support.hpp"
#include "tests/ui/image_probe.hpp"
#include "tests/ui/png_image.hpp"
#include "ui/display.hpp"

namespace acdr {
namespace {

TEST(TraineeView, WindowRunsTheAttemptAndShowsSceneHudAndScore) {
  if (!display_available()) GTEST_SKIP() << "no DISPLAY (run under xvfb-run to test windows)";
  LoadResult loaded = load_scenario_file(test::kSceneData + "empty_box.json");
  ASSERT_TRUE(loaded.ok());
  const ScenarioModel& scenario = *loaded.model;
  World world(scenario.world);
  std::vector<TrajectorySample> samples(2);
  samples[0].pose = scenario.world.instrument_start;
  samples[1].t_s = 0.5;
  samples[1].pose = scenario.world.instrument_start;
  samples[1].pose.position.z() -= 0.01;
  TrajectoryReplay replay{Trajectory(std::move(samples))};

  test::TempDir dir;
  TraineeViewOptions options;
  options.width = 800;
  options.height = 500;
  options.vsync = false;
  options.screenshot = dir.file("live.png");
  options.score_screenshot = dir.file("score.png");
  options.close_after_s = 0.0;
  options.input_label = "replay:test";
  // Driven as the attempt session drives it: open, watch the live attempt, show the score.
  TraineeView view(options);
  ASSERT_TRUE(view.can_open());
  std::string error;
  ASSERT_TRUE(view.open(scenario, world, &replay, &error)) << error;
  EXPECT_EQ(&view.device(), &replay);
  LiveAttempt attempt(scenario, world, view.device());
  attempt.start();
  view.watch(attempt);
  EXPECT_TRUE(attempt.finished());
  const AttemptRun run = attempt.wait();
  EXPECT_EQ(run.end, AttemptEnd::kInputEnded);
  EXPECT_NEAR(world.time_s(), 0.5, 0.01);
  EXPECT_GT(attempt.haptic_stats().rate_hz, 500.0);
  view.show_score(run, "Stored as attempt 1 (completed)");
  EXPECT_EQ(view.picture_error(), "");

  const test::Image live = test::load_png(options.screenshot);
  ASSERT_GT(live.width, 0) << "no live screenshot";
  EXPECT_GT(live.fraction(test::is_steel), 0.003);      // the instrument
  EXPECT_GT(live.fraction(test::is_wall_blue), 0.01);   // the box walls
  int text = 0;  // the status window's text, top right
  for (int y = 40; y < 200; ++y)
    for (int x = live.width - 300; x < live.width - 12; ++x) {
      const test::Rgb c = live.at(x, y);
      text += c.r > 170 && c.g > 170 && c.b > 170;
    }
  EXPECT_GT(text, 200);
  const test::Image score = test::load_png(options.score_screenshot);
  ASSERT_GT(score.width, 0) << "no score screenshot";
  EXPECT_GT(score.fraction([](const test::Rgb& c) { return c.g > 150 && c.g > c.r + 40; }),
            0.0003);  // PASSED / held in green
}

}  // namespace
}  // namespace acdr
