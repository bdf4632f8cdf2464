// The trainee view in mouse mode driven as a person drives it: under a display (xvfb-run),
// real pointer, wheel and key events go into the X server through XTEST, GLFW reads them from
// the window, and the instrument must move in all three axes and remove nucleus in module 02.
// The window's picture (mouse_mode_02.png in the working directory) shows the depth cue: the
// drop line to the disc and the depth gauge. Skipped without a display.
#include "ui/trainee_view.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>

#include <gtest/gtest.h>

#include "app/live_attempt.hpp"
#include "scenarios/scenario_loader.hpp"
#include "tests/ui/image_probe.hpp"
#include "tests/ui/png_image.hpp"
#include "tests/ui/xtest_user.hpp"
#include "ui/display.hpp"
#include "ui/mouse_instrument.hpp"

namespace acdr {
namespace {

using namespace std::chrono_literals;
using test::XTestUser;

TEST(TraineeViewMouse, RealPointerEventsMoveTheInstrumentInThreeAxesAndScoopNucleusOut) {
  if (!display_available()) GTEST_SKIP() << "no DISPLAY (run under xvfb-run to test windows)";
  XTestUser user;
  if (!user.ready()) GTEST_SKIP() << "the X server has no XTEST extension";
  LoadResult loaded =
      load_scenario_file(std::string(ACDR_SOURCE_DIR) + "/scenarios/modules/02_c4c5_healthy.json");
  ASSERT_TRUE(loaded.ok());
  ScenarioModel scenario = *loaded.model;
  scenario.bone.enabled = false;  // the stress worker is not what this test is about
  scenario.time_limit_s = 600;    // a loaded machine draws slowly: the input paces on frames
  World world(scenario.world);

  TraineeViewOptions options;  // 1280 x 800, as a trainee's laptop
  options.vsync = false;
  options.screenshot = "mouse_mode_02.png";  // the last live frame: the cup lifted out
  options.close_after_s = 0.0;
  TraineeView view(options);
  std::string error;
  ASSERT_TRUE(view.open(scenario, world, /*device=*/nullptr, &error)) << error;
  LiveAttempt attempt(scenario, world, view.device());

  std::atomic<bool> driven{false};
  // Each group of events waits for two more frames: the second began after the events came.
  user.set_pace([&] {
    const std::uint64_t seen = view.frames_shown();
    const auto give_up = std::chrono::steady_clock::now() + 20s;
    while (view.frames_shown() < seen + 2 && !attempt.finished() &&
           std::chrono::steady_clock::now() < give_up)
      std::this_thread::sleep_for(5ms);
  });
  std::thread hand([&] {
    if (!user.find_window("ACDR Trainer", 10s)) {
      attempt.request_stop(AttemptEnd::kStopped);
      return;
    }
    // The mouse mode's view looks from the side (+x): right on the screen is +y (toward the
    // head), up is -x (away, across the disc), and depth is -z.
    auto& device = static_cast<MouseInstrumentDevice&>(view.device());
    auto settle = [&] {  // the grip reaches its goal (20 mm/s), the physics follows
      const auto give_up = std::chrono::steady_clock::now() + 60s;
      while ((device.current().position - device.pose().position).norm() > 1e-5 &&
             !attempt.finished() && std::chrono::steady_clock::now() < give_up)
        std::this_thread::sleep_for(10ms);
      std::this_thread::sleep_for(300ms);
    };
    user.move_to(640, 400);
    user.drag(1, 12, 0);      // left-drag right: 1.2 mm toward the head, above the disc
    user.drag(1, -12, 0);     // and back
    user.drag(1, 0, -25);     // left-drag up: 2.5 mm across, where the scoop starts
    settle();
    user.wheel(10);           // dig in: wheel forward, 5 mm in
    user.drag(3, 0, 140);     // right-drag down: 14 mm deeper, the cup into the nucleus
    settle();
    user.move_to(640, 400);
    user.drag(1, 0, 45);      // scoop: left-drag down, the cup sweeps 4.5 mm toward its opening
    settle();
    user.move_to(640, 300);
    user.drag(3, 0, -250);    // lift out: right-drag up, 25 mm out with the cup's load
    settle();
    user.press_enter();      // finish the attempt
    driven = true;
  });
  attempt.start();
  view.watch(attempt);
  hand.join();
  const AttemptRun run = attempt.wait();
  view.show_score(run, "");
  EXPECT_TRUE(driven.load()) << "the trainee's window was not found";
  EXPECT_EQ(run.end, AttemptEnd::kInputEnded);  // Enter ended it
  ASSERT_FALSE(run.record.frames.empty());

  // The commanded grip's travel on each axis.
  Vec3 lo = run.record.frames.front().device.position, hi = lo;
  for (const Frame& f : run.record.frames) {
    lo = lo.cwiseMin(f.device.position);
    hi = hi.cwiseMax(f.device.position);
  }
  const Vec3 travel_mm = 1e3 * (hi - lo);
  EXPECT_GT(travel_mm.x(), 1.0) << "x travel " << travel_mm.x() << " mm";
  EXPECT_GT(travel_mm.y(), 1.0) << "y travel " << travel_mm.y() << " mm";
  EXPECT_GT(travel_mm.z(), 15.0) << "z travel " << travel_mm.z() << " mm";
  // The cup worked in the nucleus (the material pushed back, its bonds were cut) and carried
  // nucleus out of the disc space: what is outside the removal region at the end is removed.
  double peak_nucleus_N = 0.0;
  for (const Frame& f : run.record.frames) peak_nucleus_N = std::max(peak_nucleus_N, f.nucleus_force_N.norm());
  const Frame& last = run.record.frames.back();
  EXPECT_GT(peak_nucleus_N, 0.0) << "the cup never met the nucleus";
  EXPECT_GT(last.broken_bonds, 0) << "no bond of the disc was cut";
  EXPECT_GT(last.removed_target, 0) << "the scoop carried no nucleus out";
  std::printf("travel x %.1f y %.1f z %.1f mm, peak nucleus force %.3f N, %d bonds cut, removed %d "
              "nucleus and %d protected particles, %.1f s simulated at %.2fx real time\n",
              travel_mm.x(), travel_mm.y(), travel_mm.z(), peak_nucleus_N, last.broken_bonds,
              last.removed_target, last.removed_protected, last.t_s,
              run.wall_s > 0 ? last.t_s / run.wall_s : 0.0);

  // The picture: the depth gauge's column (the work between the front and the back of the
  // disc, brown) at the bottom right, and the drop line in the scene (blue: the cup is out,
  // above the disc, with its load).
  EXPECT_EQ(view.picture_error(), "");
  const test::Image picture = test::load_png(options.screenshot);
  ASSERT_EQ(picture.width, 1280);
  int gauge = 0, blue = 0;
  for (int y = 400; y < picture.height; ++y)
    for (int x = picture.width - 260; x < picture.width; ++x) {
      const test::Rgb c = picture.at(x, y);
      gauge += std::abs(c.r - 140) < 12 && std::abs(c.g - 128) < 12 && std::abs(c.b - 107) < 12;
    }
  for (int y = 0; y < picture.height; ++y)
    for (int x = 300; x < picture.width - 300; ++x) {
      const test::Rgb c = picture.at(x, y);
      blue += std::abs(c.r - 115) < 15 && std::abs(c.g - 173) < 15 && std::abs(c.b - 242) < 15;
    }
  EXPECT_GT(gauge, 500) << "no depth gauge";
  EXPECT_GT(blue, 100) << "no drop line";
}

}  // namespace
}  // namespace acdr
