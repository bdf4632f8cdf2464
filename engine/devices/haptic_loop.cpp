// Fixed-rate haptic thread.
#include "engine/devices/haptic_loop.hpp"

#include <algorithm>
#include <cmath>

#include <pthread.h>
#include <sched.h>

#ifdef __linux__
#include <sys/prctl.h>
#endif

namespace acdr {

DurationHistogram::DurationHistogram() : bins_(kBins + 1, 0) {}

void DurationHistogram::add(double seconds) {
  const double s = std::max(seconds, 0.0);
  const auto bin = static_cast<std::size_t>(std::min<double>(s / kBinWidth_s, kBins));
  ++bins_[bin];
  ++count_;
  sum_ += s;
  max_ = std::max(max_, s);
}

double DurationHistogram::quantile_s(double q) const {
  if (count_ == 0) return 0.0;
  const auto rank = static_cast<std::int64_t>(std::ceil(std::clamp(q, 0.0, 1.0) *
                                                        static_cast<double>(count_)));
  std::int64_t seen = 0;
  for (std::size_t b = 0; b < bins_.size(); ++b) {
    seen += bins_[b];
    if (seen >= std::max<std::int64_t>(rank, 1)) {
      if (b == static_cast<std::size_t>(kBins)) return max_;  // overflow bin: only the max is known
      return std::min(max_, (static_cast<double>(b) + 1.0) * kBinWidth_s);
    }
  }
  return max_;
}

HapticLoop::HapticLoop(const HapticLoopOptions& options) : options_(options) {}

HapticLoop::~HapticLoop() {
  request_stop();
  join();
}

void HapticLoop::start(Step step) {
  step_ = std::move(step);
  thread_ = std::thread([this] { run(); });
}

void HapticLoop::join() {
  if (thread_.joinable()) thread_.join();
}

HapticLoopStats HapticLoop::summarize(bool quantiles) const {
  HapticLoopStats s = published_quantiles_;
  s.target_rate_hz = options_.rate_hz;
  s.ticks = ticks_;
  s.wall_s = wall_s_;
  s.rate_hz = wall_s_ > 0 ? static_cast<double>(ticks_) / wall_s_ : 0.0;
  s.period_mean_ms = 1e3 * periods_.mean_s();
  if (quantiles) {
    s.period_p50_ms = 1e3 * periods_.quantile_s(0.5);
    s.period_p99_ms = 1e3 * periods_.quantile_s(0.99);
    s.work_p99_ms = 1e3 * work_.quantile_s(0.99);
  }
  s.period_max_ms = 1e3 * periods_.max_s();
  s.work_mean_ms = 1e3 * work_.mean_s();
  s.work_max_ms = 1e3 * work_.max_s();
  s.overruns = overruns_;
  s.resyncs = resyncs_;
  s.realtime = realtime_;
  return s;
}

HapticLoopStats HapticLoop::stats() const {
  if (finished()) return summarize(true);  // the loop thread no longer writes
  std::lock_guard lock(published_mutex_);
  return published_;
}

void HapticLoop::run() {
#ifdef __linux__
  // Timer slack is how late the kernel may wake a sleeping thread (50 µs by default); at a
  // 1 ms period that is 5 % jitter, so ask for 1 µs on this thread.
  prctl(PR_SET_TIMERSLACK, 1000UL, 0, 0, 0);
#endif
  if (options_.realtime_priority) {
    // A middle real-time priority: above every normal thread, below the kernel's own.
    sched_param param{};
    param.sched_priority = std::max(1, sched_get_priority_max(SCHED_FIFO) / 2);
    realtime_ = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) == 0;
  }
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(1.0 / std::max(options_.rate_hz, 1.0)));
  const auto max_lag = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(options_.max_lag_s));
  const auto spin = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(options_.spin_s));

  const Clock::time_point first = Clock::now();
  Clock::time_point next = first;
  Clock::time_point previous_start{};
  bool have_previous = false;
  Clock::time_point end = first;
  while (!stop_.load(std::memory_order_relaxed)) {
    if (options_.paced) {
      // Sleep to just before the deadline, then (optionally) spin the last stretch.
      if (spin.count() > 0) {
        std::this_thread::sleep_until(next - spin);
        while (Clock::now() < next) {
        }
      } else {
        std::this_thread::sleep_until(next);
      }
    }
    const Clock::time_point start = Clock::now();
    if (have_previous) periods_.add(std::chrono::duration<double>(start - previous_start).count());
    previous_start = start;
    have_previous = true;

    // An exception must not leave the thread (that would terminate the program): the loop
    // ends and its owner gets it from rethrow_failure().
    bool more = false;
    try {
      more = step_();
    } catch (...) {
      failure_ = std::current_exception();
    }

    end = Clock::now();
    const auto work = end - start;
    work_.add(std::chrono::duration<double>(work).count());
    if (work > period) ++overruns_;
    ++ticks_;
    wall_s_ = std::chrono::duration<double>(end - first).count();

    // The next deadline is on the absolute schedule; when the loop has fallen too far behind
    // (the step is slower than the period) the schedule restarts from now.
    next += period;
    if (options_.paced && end - next > max_lag) {
      next = end + period;
      ++resyncs_;
    }
    // Publish for readers without waiting for them: counters every 100 ticks, percentiles
    // (a scan of the histogram) every 1000.
    if ((ticks_ % 100) == 0) {
      const bool quantiles = (ticks_ % 1000) == 0;
      std::unique_lock lock(published_mutex_, std::try_to_lock);
      if (lock.owns_lock()) {
        published_ = summarize(quantiles);
        if (quantiles) published_quantiles_ = published_;
      }
    }
    if (!more) break;
  }
  {
    std::lock_guard lock(published_mutex_);
    published_ = summarize(true);
  }
  finished_.store(true, std::memory_order_release);
}

}  // namespace acdr
