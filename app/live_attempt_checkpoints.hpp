// Checkpoints of a live attempt, written on a thread of their own so that the physics loop never
// compresses, computes metrics or touches the database.
//
// The physics thread copies each step's new frame (and any new events and bone load samples)
// into a staging buffer (a few hundred bytes per step) and, at each checkpoint time, hands the staging buffer over by
// swapping it with an empty one under a try-lock: O(1), it never waits, and it wakes no one
// (the writer looks every 10 ms, at a priority that never preempts the loops: SCHED_BATCH,
// nice 10). If the writer has not yet taken the previous hand-over (it is still writing one
// before it), nothing is handed over this time: the data stays staged and goes with the next
// one, so nothing is lost and nothing blocks. The writer thread appends what it is given to
// its own copy of the record (the metrics of a checkpoint are those of the whole record so
// far) and calls the same CheckpointSink a headless run calls on its stepping thread
// (db/checkpoint_writer.hpp).
// Buffers circulate between the three places (staged, handed over, being written), so after
// the first rounds the physics side does not allocate unless the writer falls behind.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "app/attempt_runner.hpp"

namespace acdr {

/// What the checkpoints of a live attempt cost and achieved (exact after finish()).
struct LiveCheckpointStats {
  std::int64_t handed_over = 0;  ///< hand-overs to the writer thread
  /// Checkpoint times at which the writer had not yet taken the previous hand-over (or held
  /// the lock for its swap): the data went with the next hand-over.
  std::int64_t deferred = 0;
  std::int64_t saved = 0;   ///< sink calls that saved
  std::int64_t failed = 0;  ///< sink calls that did not (the next one carries their part)
  std::int64_t frames_saved = 0;  ///< frames in saved checkpoints
  std::size_t largest_frames = 0;  ///< largest hand-over (frames)
  double handover_max_ms = 0.0;    ///< physics thread: one hand-over (try-lock, swap)
  double write_mean_ms = 0.0;      ///< writer thread: one sink call (encode, metrics, compress,
  double write_max_ms = 0.0;       ///< transaction), per checkpoint
  bool background_priority = false;  ///< the writer runs at SCHED_BATCH, nice 10 (Linux)
  bool writer_out_of_memory = false;  ///< the writer ran out of memory and stopped early
};

class LiveAttemptCheckpoints {
 public:
  /// `sink` runs on the writer thread, with views of the writer's own copy of the record
  /// (whose summary is `summary`). `frames_per_checkpoint` sizes the buffers.
  LiveAttemptCheckpoints(CheckpointSink sink, const WorldSummary& summary,
                         std::size_t frames_per_checkpoint);
  /// finish(false) if not yet done.
  ~LiveAttemptCheckpoints();
  LiveAttemptCheckpoints(const LiveAttemptCheckpoints&) = delete;
  LiveAttemptCheckpoints& operator=(const LiveAttemptCheckpoints&) = delete;

  /// Starts the writer thread. Call once, before the first step.
  void start();

  // --- the physics thread ---
  /// Copies what `record` gained since the last call (usually one frame) into the staging
  /// buffer. `record` is the stepper's, which only ever grows.
  void stage(const AttemptRecording& record);
  /// At a checkpoint time (`t_s`: simulated time so far, s): hands the staged part to the
  /// writer; never waits. Returns false (data stays staged) when the writer has not taken the
  /// previous hand-over yet.
  bool hand_over(double t_s);

  // --- any thread, once the physics thread has stopped stepping and been joined ---
  /// `flush`: hands over what is still staged (e.g. an abandoned attempt, which keeps only
  /// what was checkpointed). Then waits for the writer to write everything it was given, and
  /// ends it. Call once; later calls do nothing.
  void finish(bool flush);

  /// Exact after finish().
  LiveCheckpointStats stats() const;

 private:
  struct Batch {
    std::vector<Frame> frames;
    std::vector<Event> events;
    std::vector<BoneLoadRecord> bone_loads;
    double t_s = 0.0;
    void clear() {
      frames.clear();
      events.clear();
      bone_loads.clear();
    }
  };

  void run();
  void run_guarded();  ///< run() on the writer thread, ending it if memory runs out

  CheckpointSink sink_;
  // Physics thread only.
  Batch staging_;
  std::size_t staged_frames_ = 0, staged_events_ = 0, staged_bone_ = 0;  ///< of the stepper's record
  double staged_t_ = 0.0;  ///< time of the last staged frame (s)
  // Guarded by mutex_.
  std::mutex mutex_;
  std::condition_variable wake_;
  Batch slot_;
  bool slot_full_ = false;
  bool stopping_ = false;
  // Writer thread only.
  Batch work_;
  AttemptRecording mirror_;  ///< the record so far, as handed over
  std::size_t saved_frames_ = 0, saved_events_ = 0, saved_bone_ = 0;  ///< of mirror_, saved
  double write_total_ms_ = 0.0;
  std::thread thread_;
  bool finished_ = false;
  // Physics side (hand_over) and writer side (run) each write their own fields; read after
  // finish() joined the writer (and the physics thread was joined before).
  LiveCheckpointStats stats_;
};

}  // namespace acdr
