// A job run beside the caller (see the header).
#include "engine/core/step_worker.hpp"

#include <utility>

namespace acdr {

StepWorker::StepWorker(std::function<void()> job, bool own_thread) : job_(std::move(job)) {
  if (own_thread) thread_ = std::thread([this] { loop(); });
}

StepWorker::~StepWorker() {
  if (!thread_.joinable()) return;
  {
    std::unique_lock lock(mutex_);
    done_.wait(lock, [this] { return !running_; });
    stop_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

void StepWorker::launch() {
  wait();
  if (!thread_.joinable()) {
    const auto start = std::chrono::steady_clock::now();
    job_();
    last_run_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return;
  }
  {
    std::lock_guard lock(mutex_);
    running_ = true;
  }
  collected_ = false;
  wake_.notify_one();
}

void StepWorker::wait() {
  if (collected_) return;  // no lock when the last run was already waited for
  std::exception_ptr error;
  {
    std::unique_lock lock(mutex_);
    done_.wait(lock, [this] { return !running_; });
    std::swap(error, error_);
    last_run_s_ = run_s_;
  }
  collected_ = true;
  if (error) std::rethrow_exception(error);
}

bool StepWorker::wait_until(std::chrono::steady_clock::time_point deadline) {
  if (collected_) return true;
  {
    std::unique_lock lock(mutex_);
    if (!done_.wait_until(lock, deadline, [this] { return !running_; })) return false;
  }
  wait();  // collects the run (and its error)
  return true;
}

void StepWorker::loop() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return running_ || stop_; });
    if (stop_) return;
    lock.unlock();
    std::exception_ptr error;
    const auto start = std::chrono::steady_clock::now();
    try {
      job_();
    } catch (...) {
      error = std::current_exception();
    }
    const auto end = std::chrono::steady_clock::now();
    lock.lock();
    error_ = error;
    run_s_ = std::chrono::duration<double>(end - start).count();
    running_ = false;
    done_.notify_all();
  }
}

}  // namespace acdr
