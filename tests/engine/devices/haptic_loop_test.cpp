// The haptic loop: paced at its rate by the clock, measuring what it achieved, and reporting
// honestly (rate, overruns) when the step is slower than the period.
#include "engine/devices/haptic_loop.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <new>
#include <thread>

namespace acdr {
namespace {

void busy_for(double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
  }
}

TEST(DurationHistogram, QuantilesToWithinABin) {
  DurationHistogram h;
  for (int i = 1; i <= 100; ++i) h.add(i * 1e-4);  // 0.1 .. 10 ms
  EXPECT_EQ(h.count(), 100);
  EXPECT_NEAR(h.quantile_s(0.5), 5.0e-3, DurationHistogram::kBinWidth_s + 1e-12);
  EXPECT_NEAR(h.quantile_s(0.99), 9.9e-3, DurationHistogram::kBinWidth_s + 1e-12);
  EXPECT_DOUBLE_EQ(h.quantile_s(1.0), 10e-3);
  EXPECT_DOUBLE_EQ(h.max_s(), 10e-3);
  EXPECT_NEAR(h.mean_s(), 5.05e-3, 1e-12);
  h.add(1.0);  // beyond the last bin: still counted, max exact
  EXPECT_DOUBLE_EQ(h.quantile_s(1.0), 1.0);
}

TEST(HapticLoop, PacedLoopHoldsItsRate) {
  HapticLoopOptions options;
  options.rate_hz = 1000.0;
  HapticLoop loop(options);
  int ticks = 0;
  loop.start([&] { return ++ticks < 300; });
  loop.join();
  const HapticLoopStats s = loop.stats();
  EXPECT_EQ(s.ticks, 300);
  // The loop is paced: it never runs ahead of its schedule. How close it stays to 1 kHz depends
  // on the host (a loaded machine wakes the thread late), so the achieved rate is printed, not
  // asserted; `acdr run --json` reports it per attempt (haptics.rate_hz) and the bench measures
  // it.
  EXPECT_LE(s.rate_hz, 1000.0 * 1.01);
  EXPECT_GE(s.period_mean_ms, 0.99);
  EXPECT_GT(s.period_p99_ms, 0.0);
  std::printf("[ info     ] paced loop: %.1f Hz, mean period %.3f ms, p99 %.3f ms, %lld overruns\n",
              s.rate_hz, s.period_mean_ms, s.period_p99_ms, static_cast<long long>(s.overruns));
}

TEST(HapticLoop, ASlowStepIsReportedNotHidden) {
  HapticLoopOptions options;
  options.rate_hz = 1000.0;
  HapticLoop loop(options);
  int ticks = 0;
  loop.start([&] {
    busy_for(2.5e-3);  // 2.5x the period
    return ++ticks < 60;
  });
  loop.join();
  const HapticLoopStats s = loop.stats();
  EXPECT_EQ(s.overruns, 60);
  EXPECT_LT(s.rate_hz, 500.0);
  EXPECT_GE(s.period_p99_ms, 2.5);
  EXPECT_GE(s.work_mean_ms, 2.5);
  EXPECT_GT(s.resyncs, 0);  // it fell behind and restarted its schedule, no burst
}

TEST(HapticLoop, StopsOnRequestAndPublishesWhileRunning) {
  HapticLoop loop;
  std::atomic<int> ticks{0};
  loop.start([&] {
    ++ticks;
    return true;
  });
  while (ticks.load() < 250) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_FALSE(loop.finished());
  EXPECT_GE(loop.stats().ticks, 100);  // published every 100 ticks
  loop.request_stop();
  loop.join();
  EXPECT_TRUE(loop.finished());
  EXPECT_EQ(loop.stats().ticks, ticks.load());
}

TEST(HapticLoop, UnpacedLoopRunsBackToBack) {
  HapticLoopOptions options;
  options.rate_hz = 100.0;  // would take 2 s paced
  options.paced = false;
  HapticLoop loop(options);
  int ticks = 0;
  const auto start = std::chrono::steady_clock::now();
  loop.start([&] { return ++ticks < 200; });
  loop.join();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
  EXPECT_GT(loop.stats().rate_hz, 1000.0);
}

// A step that throws (here: out of memory) must not take the program down with its thread:
// the loop ends at that tick and hands the exception to its owner.
TEST(HapticLoop, AStepThatThrowsEndsTheLoopAndItsOwnerGetsTheException) {
  HapticLoopOptions options;
  options.paced = false;
  HapticLoop loop(options);
  int ticks = 0;
  loop.start([&]() -> bool {
    if (++ticks == 10) throw std::bad_alloc();
    return true;
  });
  loop.join();
  EXPECT_TRUE(loop.finished());
  EXPECT_TRUE(loop.failed());
  EXPECT_EQ(ticks, 10);
  EXPECT_THROW(loop.rethrow_failure(), std::bad_alloc);
}

TEST(HapticLoop, ALoopThatEndsNormallyHasNoFailure) {
  HapticLoopOptions options;
  options.paced = false;
  HapticLoop loop(options);
  int ticks = 0;
  loop.start([&] { return ++ticks < 5; });
  loop.join();
  EXPECT_FALSE(loop.failed());
  EXPECT_NO_THROW(loop.rethrow_failure());
}

}  // namespace
}  // namespace acdr
