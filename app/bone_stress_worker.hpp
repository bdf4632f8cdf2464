// The bone's finite-element solves beside an attempt, on a thread of their own: never in the
// fixed step, never waited for by it. The stepping thread hands over each load sample the world
// takes (every BoneModelConfig::sample_period_s of simulated time); the worker builds the two
// vertebrae (meshes from the cache, one factorisation each) and then solves the samples in the
// order they came, summing them with the same BoneStressHistory a re-score uses, so the
// attempt's bone metrics are identical live, headless and re-scored. When it falls behind it
// catches up (the samples wait in a queue); finish() waits for the last one. Like the
// checkpoint writer it runs at background priority, so it never takes a core from the device
// and physics loops.
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "engine/bone/bone_stress_history.hpp"
#include "engine/core/latest_value.hpp"

namespace acdr {

/// What the worker's solves cost (wall time), for reports and `acdr run --json`.
struct BoneWorkerStats {
  double build_s = 0.0;          ///< meshing or cache load, regions, factorisation
  std::int64_t samples = 0;      ///< load samples handled
  std::int64_t solves = 0;       ///< vertebra solves (loaded vertebrae)
  double mean_sample_ms = 0.0;   ///< per sample with at least one solve (wall)
  double max_sample_ms = 0.0;
  /// The same in CPU time of the worker thread: what a sample costs one core, whatever else
  /// the machine runs.
  double mean_sample_cpu_ms = 0.0;
  double mean_solve_cpu_ms = 0.0;  ///< per vertebra solve
  double lag_s = 0.0;            ///< largest wait of a sample in the queue (wall)
  bool background_priority = false;  ///< the thread's priority was lowered
};

/// Every element's stress of both vertebrae at one solved sample, for a live stress view.
struct BoneStressField {
  BoneSampleResult result;
  /// Per vertebra, per tetrahedron (Pa; in shell elements the shell's own); empty when the
  /// vertebra was not loaded enough to solve.
  std::array<std::vector<float>, 2> element_von_mises_Pa;
  std::vector<BoneLoadPoint> loads;  ///< the sample's loads
};

class BoneStressWorker {
 public:
  /// Starts the thread. `anatomy` must outlive the worker; meshes are cached in `cache_dir`.
  BoneStressWorker(const Anatomy& anatomy, const BoneModelConfig& config, std::string cache_dir);
  ~BoneStressWorker();
  BoneStressWorker(const BoneStressWorker&) = delete;
  BoneStressWorker& operator=(const BoneStressWorker&) = delete;

  /// From the stepping thread: queues a sample. Never waits and wakes nobody (the worker looks
  /// every 5 ms): when the queue is busy the sample is kept and handed over with the next one
  /// (or by finish()).
  void push(const BoneLoadRecord& sample);
  /// Waits until every sample is solved and stops the thread. Returns false with `error` set
  /// when the bone could not be built.
  bool finish(BoneStressSummary* summary, BoneWorkerStats* stats, std::string* error);
  /// The newest solved sample (for a live display), version 0 before the first.
  LatestValue<BoneSampleResult>& latest() { return latest_; }

  /// From any thread: while on, the worker solves a sample in full (every element, not only
  /// the measured ones: the same metrics bit for bit) when it has caught up (no sample waiting)
  /// and the last field is at least kFieldPeriod_s old, or, while it is behind, when the last
  /// one is kFieldBehindPeriod_s old; it publishes it in latest_field().
  void set_field_wanted(bool on) { field_wanted_.store(on, std::memory_order_relaxed); }
  LatestValue<BoneStressField>& latest_field() { return latest_field_; }
  static constexpr double kFieldPeriod_s = 0.1;
  static constexpr double kFieldBehindPeriod_s = 1.0;
  /// The built model, null before it is built (or when it could not be). Immutable and alive
  /// as long as the worker: a display may read its meshes from any thread.
  const BoneSegment* bone() const { return bone_ptr_.load(std::memory_order_acquire); }

 private:
  void run();
  void run_guarded();  ///< run() on the worker thread, ending it if memory runs out

  const Anatomy& anatomy_;
  BoneModelConfig config_;
  std::string cache_dir_;
  std::vector<BoneLoadRecord> pending_;  // stepping thread only
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::pair<BoneLoadRecord, double>> queue_;  // with the wall time it was queued
  bool closing_ = false;
  // Written by the worker, read after join.
  BoneStressSummary summary_;
  BoneWorkerStats stats_;
  std::string error_;
  LatestValue<BoneSampleResult> latest_;
  std::atomic<bool> field_wanted_{false};
  LatestValue<BoneStressField> latest_field_;
  std::unique_ptr<BoneSegment> bone_;  // written by the worker before bone_ptr_ is set
  std::atomic<const BoneSegment*> bone_ptr_{nullptr};
  std::thread thread_;
};

}  // namespace acdr
