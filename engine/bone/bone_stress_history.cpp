// Summing the bone's stresses sample by sample.
#include "engine/bone/bone_stress_history.hpp"

#include <algorithm>

namespace acdr {

void BoneStressHistory::add(const BoneSampleResult& s) {
  BoneStressSummary& out = summary_;
  ++out.samples;
  out.solves += (s.solved[0] ? 1 : 0) + (s.solved[1] ? 1 : 0);
  const double endplate_before = std::max(out.peak_Pa[0], out.peak_Pa[1]);
  for (int m = 0; m < kBoneMeasureCount; ++m) out.peak_Pa[m] = std::max(out.peak_Pa[m], s.peak_Pa[m]);
  const double endplate = std::max(s.peak_Pa[0], s.peak_Pa[1]);
  if (endplate > endplate_before) out.peak_stress_t_s = s.t_s;
  const double posterior = std::max(s.peak_Pa[2], s.peak_Pa[3]);
  if (endplate > strengths_.warning_fraction * strengths_.endplate_Pa)
    out.endplate_over_warning_s += period_s_;
  if (posterior > strengths_.warning_fraction * strengths_.posterior_Pa)
    out.posterior_over_warning_s += period_s_;
  if (s.load_N > out.peak_load_N) {
    out.peak_load_N = s.load_N;
    out.peak_load_t_s = s.t_s;
  }
}

BoneStressSummary analyse_bone_loads(const BoneSegment& bone,
                                     std::span<const BoneLoadRecord> samples) {
  BoneStressHistory history(bone.config().strengths, bone.config().sample_period_s);
  BoneSegmentScratch scratch;
  for (const BoneLoadRecord& r : samples) history.add(bone.solve(r.t_s, r.points, scratch));
  return history.summary();
}

}  // namespace acdr
