// The bone's stresses over an attempt, one load sample after another: peaks per measure, time
// above the warning fraction of strength, the moment of the largest load. The same class sums
// a live attempt on its worker thread and a recording afterwards, in the same order, so the
// two give the same figures bit for bit.
#pragma once

#include <span>

#include "engine/bone/bone_segment.hpp"
#include "engine/bone/bone_stress_summary.hpp"

namespace acdr {

class BoneStressHistory {
 public:
  /// `period_s`: the time each sample stands for (the sampling period).
  BoneStressHistory(const BoneStrengths& strengths, double period_s)
      : strengths_(strengths), period_s_(period_s) {}
  void add(const BoneSampleResult& sample);
  const BoneStressSummary& summary() const { return summary_; }

 private:
  BoneStrengths strengths_;
  double period_s_ = 0.0;
  BoneStressSummary summary_;
};

/// Solves every recorded sample in order and sums them (a recording's bone metrics).
BoneStressSummary analyse_bone_loads(const BoneSegment& bone,
                                     std::span<const BoneLoadRecord> samples);

}  // namespace acdr
