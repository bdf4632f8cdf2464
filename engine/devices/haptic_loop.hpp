// The haptic loop: a thread of its own that calls a step function at a fixed rate (>= 1 kHz,
// docs/references.md, Haptics; the seed ran 1.5 kHz), paced by an absolute clock (sleep_until the
// next tick, so errors do not accumulate), independent of rendering. It measures what it
// achieved — ticks per second, the period between tick starts (mean, p99, max), the work time
// per tick, overruns — and reports honestly when the step cannot keep up: it does not burst
// to catch up; after falling `max_lag_s` behind it restarts its schedule from now (counted).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace acdr {

struct HapticLoopOptions {
  double rate_hz = 1000.0;  ///< ticks per second; 1 kHz is the haptic standard
  /// true: paced by the clock (live devices); false: ticks back to back, as fast as the step
  /// allows (the rate is still measured).
  bool paced = true;
  /// Falling this far behind the schedule drops the backlog: the next tick is due one period
  /// from now (a "resync") instead of a burst of late ticks. Default 20 ms.
  double max_lag_s = 0.02;
  /// Busy-wait this long before each deadline instead of sleeping (s): lower period jitter at
  /// the cost of a busy core. 0 by default (the machine is shared); Linux's timer slack is
  /// reduced to 1 µs on the loop's thread either way.
  double spin_s = 0.0;
  /// Ask the OS for real-time scheduling (SCHED_FIFO) on the loop's thread, as haptic
  /// drivers do. Needs the privilege (root or CAP_SYS_NICE, or an rtprio limit); whether it
  /// was granted is reported in HapticLoopStats::realtime. Off by default.
  bool realtime_priority = false;
};

/// What the loop achieved. Periods and work times in milliseconds.
struct HapticLoopStats {
  double target_rate_hz = 0.0;
  std::int64_t ticks = 0;
  double wall_s = 0.0;             ///< from the first tick's start to the last tick's end
  double rate_hz = 0.0;            ///< ticks / wall_s
  double period_mean_ms = 0.0;     ///< tick start to next tick start
  double period_p50_ms = 0.0;
  double period_p99_ms = 0.0;
  double period_max_ms = 0.0;
  double work_mean_ms = 0.0;       ///< time spent inside the step function
  double work_p99_ms = 0.0;
  double work_max_ms = 0.0;
  std::int64_t overruns = 0;       ///< ticks whose work took longer than one period
  std::int64_t resyncs = 0;        ///< schedule restarts after falling max_lag_s behind
  bool realtime = false;           ///< the thread ran with real-time priority
};

/// A histogram of durations in fixed 10 µs bins up to 100 ms (plus an overflow bin): O(1)
/// insert without allocation, percentiles to within one bin.
class DurationHistogram {
 public:
  DurationHistogram();
  void add(double seconds);
  std::int64_t count() const { return count_; }
  double mean_s() const { return count_ ? sum_ / static_cast<double>(count_) : 0.0; }
  double max_s() const { return max_; }
  /// The q-quantile (0..1), as the upper edge of its bin (s); the exact max for the last bin.
  double quantile_s(double q) const;

  static constexpr double kBinWidth_s = 10e-6;
  static constexpr int kBins = 10000;

 private:
  std::vector<std::int64_t> bins_;  ///< kBins + 1 (overflow)
  std::int64_t count_ = 0;
  double sum_ = 0.0;
  double max_ = 0.0;
};

class HapticLoop {
 public:
  /// One step; return false to end the loop. Runs on the loop's thread.
  using Step = std::function<bool()>;

  explicit HapticLoop(const HapticLoopOptions& options = {});
  /// Requests a stop and waits for the thread.
  ~HapticLoop();
  HapticLoop(const HapticLoop&) = delete;
  HapticLoop& operator=(const HapticLoop&) = delete;

  /// Starts the thread, which calls `step` at the configured rate until it returns false or
  /// request_stop() is called. Call once.
  void start(Step step);
  /// Asks the loop to end after the current tick (any thread).
  void request_stop() { stop_.store(true, std::memory_order_relaxed); }
  /// Waits for the loop's thread to end.
  void join();
  /// True once the loop has ended (its step returned false or threw, or a stop was honoured).
  bool finished() const { return finished_.load(std::memory_order_acquire); }
  /// After join(): if the step threw (out of memory, say), the loop ended there and this
  /// throws the same exception on the calling thread, so the owner handles it as if the step
  /// had run there; otherwise it does nothing.
  void rethrow_failure() const {
    if (failure_) std::rethrow_exception(failure_);
  }
  /// After join(): whether the step threw.
  bool failed() const { return static_cast<bool>(failure_); }

  /// Statistics so far: exact after join(); while running, as of the last publication (the
  /// loop publishes every ~100 ticks without waiting for readers).
  HapticLoopStats stats() const;

 private:
  void run();
  // The stats from the counters; percentiles computed only when `quantiles` (else the last
  // computed ones are carried).
  HapticLoopStats summarize(bool quantiles) const;

  HapticLoopOptions options_;
  Step step_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> finished_{false};
  std::exception_ptr failure_;  ///< what the step threw; written by the loop thread before finished_

  // Owned by the loop thread while it runs.
  DurationHistogram periods_;
  DurationHistogram work_;
  std::int64_t ticks_ = 0;
  std::int64_t overruns_ = 0;
  std::int64_t resyncs_ = 0;
  double wall_s_ = 0.0;
  bool realtime_ = false;

  mutable std::mutex published_mutex_;
  HapticLoopStats published_;            ///< guarded by published_mutex_
  HapticLoopStats published_quantiles_;  ///< last stats with percentiles (loop thread)
};

}  // namespace acdr
