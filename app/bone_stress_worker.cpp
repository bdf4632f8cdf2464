// The bone's solver thread: see bone_stress_worker.hpp.
#include "app/bone_stress_worker.hpp"

#include "app/background_priority.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <new>

namespace acdr {
namespace {
double wall_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
double thread_cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
}  // namespace

BoneStressWorker::BoneStressWorker(const Anatomy& anatomy, const BoneModelConfig& config,
                                   std::string cache_dir)
    : anatomy_(anatomy), config_(config), cache_dir_(std::move(cache_dir)) {
  pending_.reserve(16);
  thread_ = std::thread([this] { run_guarded(); });
}

BoneStressWorker::~BoneStressWorker() {
  {
    std::lock_guard lock(mutex_);
    closing_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
}

void BoneStressWorker::push(const BoneLoadRecord& sample) {
  pending_.push_back(sample);
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;  // handed over with the next sample
  const double now = wall_now();
  for (BoneLoadRecord& r : pending_) queue_.emplace_back(std::move(r), now);
  pending_.clear();
  // No wake-up call on the stepping thread's path: the worker looks every few milliseconds.
}

bool BoneStressWorker::finish(BoneStressSummary* summary, BoneWorkerStats* stats,
                              std::string* error) {
  {
    std::lock_guard lock(mutex_);
    const double now = wall_now();
    for (BoneLoadRecord& r : pending_) queue_.emplace_back(std::move(r), now);
    pending_.clear();
    closing_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
  if (summary) *summary = summary_;
  if (stats) *stats = stats_;
  if (error) *error = error_;
  return error_.empty();
}

void BoneStressWorker::run() {
  // Never take a core from the device and physics loops (background_priority.hpp).
  stats_.background_priority = lower_this_threads_priority();
  const auto t0 = std::chrono::steady_clock::now();
  std::string why;
  bone_ = BoneSegment::build(anatomy_, config_, cache_dir_, &why);
  const BoneSegment* bone = bone_.get();
  bone_ptr_.store(bone, std::memory_order_release);
  stats_.build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!bone) error_ = why.empty() ? "the bone model could not be built" : why;
  BoneStressHistory history(config_.strengths, config_.sample_period_s);
  BoneSegmentScratch scratch;
  double solved_ms = 0.0, solved_cpu_ms = 0.0, last_field = -1e9;
  std::int64_t solved_samples = 0;
  for (;;) {
    std::pair<BoneLoadRecord, double> item;
    bool caught_up = false;
    {
      std::unique_lock lock(mutex_);
      while (!closing_ && queue_.empty()) wake_.wait_for(lock, std::chrono::milliseconds(5));
      if (queue_.empty()) break;  // closing and drained
      item = std::move(queue_.front());
      queue_.pop_front();
      caught_up = queue_.empty();
    }
    if (!bone) continue;  // drain: nothing to solve with
    const double start = wall_now();
    const double cpu_start = thread_cpu_now();
    stats_.lag_s = std::max(stats_.lag_s, start - item.second);
    // A live stress view wants every element now and then: this sample in full, when nothing
    // waits behind it, or once a second while the worker is behind (a busy machine).
    const double since_field = start - last_field;
    scratch.nodal_fields = field_wanted_.load(std::memory_order_relaxed) &&
                           ((caught_up && since_field >= kFieldPeriod_s) ||
                            since_field >= kFieldBehindPeriod_s);
    const BoneSampleResult r = bone->solve(item.first.t_s, item.first.points, scratch);
    if (scratch.nodal_fields && (r.solved[0] || r.solved[1])) {
      last_field = start;
      latest_field_.try_publish([&](BoneStressField& f) {
        f.result = r;
        for (int v = 0; v < 2; ++v) {
          const auto& vm = scratch.solution[v].element_von_mises_Pa;
          f.element_von_mises_Pa[v].assign(r.solved[v] ? vm.begin() : vm.end(), vm.end());
        }
        f.loads = item.first.points;
      });
    }
    history.add(r);
    ++stats_.samples;
    if (r.solved[0] || r.solved[1]) {
      const double ms = (wall_now() - start) * 1e3;
      solved_ms += ms;
      solved_cpu_ms += (thread_cpu_now() - cpu_start) * 1e3;
      ++solved_samples;
      stats_.max_sample_ms = std::max(stats_.max_sample_ms, ms);
      latest_.try_publish([&](BoneSampleResult& v) { v = r; });
    }
  }
  summary_ = history.summary();
  stats_.solves = summary_.solves;
  stats_.mean_sample_ms = solved_samples > 0 ? solved_ms / solved_samples : 0.0;
  stats_.mean_sample_cpu_ms = solved_samples > 0 ? solved_cpu_ms / solved_samples : 0.0;
  stats_.mean_solve_cpu_ms = stats_.solves > 0 ? solved_cpu_ms / stats_.solves : 0.0;
}

void BoneStressWorker::run_guarded() {
  // Out of memory while meshing, factorising or solving ends the bone model, not the program:
  // the attempt goes on without its stress metrics, and finish() says why.
  try {
    run();
  } catch (const std::bad_alloc&) {
    error_ = "out of memory in the bone model (its mesh or factorisation); no bone stress for this attempt";
  }
}

}  // namespace acdr
