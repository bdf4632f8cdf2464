// The checkpoint writer thread of a live attempt: see live_attempt_checkpoints.hpp.
#include "app/live_attempt_checkpoints.hpp"

#include "app/background_priority.hpp"

#include <algorithm>
#include <chrono>
#include <new>
#include <utility>

namespace acdr {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// How often the writer looks for a hand-over. The physics thread does not wake it (no futex
// call, no wake-up on its path); a checkpoint is due every few seconds, so 10 ms is prompt.
constexpr auto kPollPeriod = std::chrono::milliseconds(10);

// The writer must never take a core from the device and physics loops (measured before
// lowering its priority: woken at a hand-over, it took the physics thread's core for up to 7 ms
// on a loaded 2-core machine); background_priority.hpp says how. Nice 10 still leaves it
// several times what checkpoints need.

}  // namespace

LiveAttemptCheckpoints::LiveAttemptCheckpoints(CheckpointSink sink, const WorldSummary& summary,
                                               std::size_t frames_per_checkpoint)
    : sink_(std::move(sink)) {
  // Room for a late writer (two intervals) before the staging buffer has to grow.
  const std::size_t frames = 2 * frames_per_checkpoint + 16;
  for (Batch* b : {&staging_, &slot_, &work_}) {
    b->frames.reserve(frames);
    b->events.reserve(256);
    b->bone_loads.reserve(frames / 8 + 16);  // a sample every 10 ms at a 1 ms step, with room
  }
  mirror_.summary = summary;
}

LiveAttemptCheckpoints::~LiveAttemptCheckpoints() { finish(false); }

void LiveAttemptCheckpoints::start() {
  thread_ = std::thread([this] { run_guarded(); });
}

void LiveAttemptCheckpoints::stage(const AttemptRecording& record) {
  if (record.frames.size() > staged_frames_) {
    staging_.frames.insert(staging_.frames.end(),
                           record.frames.begin() + static_cast<long>(staged_frames_),
                           record.frames.end());
    staged_frames_ = record.frames.size();
    staged_t_ = record.frames.back().t_s;
  }
  if (record.bone_loads.size() > staged_bone_) {
    // A bone sample every 10 ms or so: its loads are copied (one small allocation, as the
    // stepper's own record and its hand-over to the bone's solver thread make for it).
    staging_.bone_loads.insert(staging_.bone_loads.end(),
                               record.bone_loads.begin() + static_cast<long>(staged_bone_),
                               record.bone_loads.end());
    staged_bone_ = record.bone_loads.size();
  }
  if (record.events.size() > staged_events_) {
    staging_.events.insert(staging_.events.end(),
                           record.events.begin() + static_cast<long>(staged_events_),
                           record.events.end());
    staged_events_ = record.events.size();
  }
}

bool LiveAttemptCheckpoints::hand_over(double t_s) {
  const auto start = Clock::now();
  std::size_t frames = 0;
  {
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock() || slot_full_) {
      ++stats_.deferred;
      return false;
    }
    // slot_ is the empty buffer the writer left (capacity kept): an O(1) swap.
    std::swap(slot_, staging_);
    slot_.t_s = t_s;
    slot_full_ = true;
    frames = slot_.frames.size();
  }
  stats_.largest_frames = std::max(stats_.largest_frames, frames);
  ++stats_.handed_over;
  stats_.handover_max_ms = std::max(stats_.handover_max_ms, ms_since(start));
  return true;
}

void LiveAttemptCheckpoints::run() {
  stats_.background_priority = lower_this_threads_priority();
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      while (!slot_full_ && !stopping_) wake_.wait_for(lock, kPollPeriod);
      if (!slot_full_) return;  // stopping, and everything given was written
      std::swap(work_, slot_);  // work_ was cleared after its last use
      slot_full_ = false;
    }
    mirror_.frames.insert(mirror_.frames.end(), work_.frames.begin(), work_.frames.end());
    mirror_.events.insert(mirror_.events.end(), work_.events.begin(), work_.events.end());
    mirror_.bone_loads.insert(mirror_.bone_loads.end(), work_.bone_loads.begin(),
                              work_.bone_loads.end());
    const auto start = Clock::now();
    const bool saved =
        sink_(CheckpointView{mirror_, saved_frames_, saved_events_, work_.t_s, saved_bone_});
    const double ms = ms_since(start);
    if (saved) {
      stats_.frames_saved += static_cast<std::int64_t>(mirror_.frames.size() - saved_frames_);
      saved_frames_ = mirror_.frames.size();
      saved_events_ = mirror_.events.size();
      saved_bone_ = mirror_.bone_loads.size();
      ++stats_.saved;
    } else {
      ++stats_.failed;  // the next call carries this part as well
    }
    write_total_ms_ += ms;
    stats_.write_max_ms = std::max(stats_.write_max_ms, ms);
    work_.clear();
  }
}

void LiveAttemptCheckpoints::finish(bool flush) {
  if (finished_) return;
  finished_ = true;
  if (!thread_.joinable()) return;
  {
    std::lock_guard lock(mutex_);
    if (flush && (!staging_.frames.empty() || !staging_.events.empty() ||
                  !staging_.bone_loads.empty())) {
      const double t = staged_t_;
      if (slot_full_) {
        // The writer has not taken the last hand-over yet: this goes with it.
        slot_.frames.insert(slot_.frames.end(), staging_.frames.begin(), staging_.frames.end());
        slot_.events.insert(slot_.events.end(), staging_.events.begin(), staging_.events.end());
        slot_.bone_loads.insert(slot_.bone_loads.end(), staging_.bone_loads.begin(),
                                staging_.bone_loads.end());
      } else {
        std::swap(slot_, staging_);
        slot_full_ = true;
      }
      slot_.t_s = t;
      staging_.clear();
    }
    stopping_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

LiveCheckpointStats LiveAttemptCheckpoints::stats() const {
  LiveCheckpointStats s = stats_;
  const std::int64_t writes = s.saved + s.failed;
  s.write_mean_ms = writes > 0 ? write_total_ms_ / static_cast<double>(writes) : 0.0;
  return s;
}

void LiveAttemptCheckpoints::run_guarded() {
  // Out of memory on this thread ends the checkpoints, not the program: the attempt goes on
  // and its whole recording is stored when it ends.
  try {
    run();
  } catch (const std::bad_alloc&) {
    stats_.writer_out_of_memory = true;
  }
}

}  // namespace acdr
