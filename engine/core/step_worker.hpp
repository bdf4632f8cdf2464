// A job run beside the caller: one thread of its own that runs the same job each time it is
// launched, while the caller goes on; wait() returns once that run has finished. The job's
// writes are visible to the caller after wait() (the hand-over is under a mutex), and an
// exception thrown by the job is rethrown by wait(). Without a thread of its own (own_thread
// false) launch() runs the job at once, so the results are the same either way and only when
// the work is done differs. The thread is made at construction: launching allocates nothing.
// launch() and wait() are for one calling thread.
#pragma once

#include <chrono>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace acdr {

class StepWorker {
 public:
  StepWorker(std::function<void()> job, bool own_thread);
  ~StepWorker();  // waits for a run in progress, then ends the thread
  StepWorker(const StepWorker&) = delete;
  StepWorker& operator=(const StepWorker&) = delete;

  /// Starts a run of the job (waits first for the one before, if any).
  void launch();
  /// Returns once the last run launched has finished (at once when none is in progress).
  void wait();
  /// Waits for the run in progress until `deadline` at most; true when it has finished.
  bool wait_until(std::chrono::steady_clock::time_point deadline);
  /// The wall time of the last finished run, s.
  double last_run_s() const { return last_run_s_; }

 private:
  void loop();

  std::function<void()> job_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable done_;
  bool running_ = false;  // a run was launched and has not finished
  bool collected_ = true;  // the caller's own: the last run was waited for (no lock needed)
  bool stop_ = false;
  std::exception_ptr error_;
  double run_s_ = 0.0;       // under mutex_: the worker's timing of its last run
  double last_run_s_ = 0.0;  // the caller's copy
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace acdr
