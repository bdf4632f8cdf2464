// Bone-stress metrics from the summary of the bone's solves.
#include "assessment/bone_metrics.hpp"

#include <algorithm>

namespace acdr {

void add_bone_metrics(const BoneStressSummary& s, Metrics& m) {
  const auto& p = s.peak_Pa;
  auto mpa = [](double pa) { return pa * 1e-6; };
  m.set("endplate_c4_peak_stress_MPa", mpa(p[static_cast<int>(BoneMeasure::kC4InferiorEndplate)]));
  m.set("endplate_c5_peak_stress_MPa", mpa(p[static_cast<int>(BoneMeasure::kC5SuperiorEndplate)]));
  m.set("endplate_peak_stress_MPa", mpa(std::max(p[0], p[1])));
  m.set("posterior_peak_stress_MPa", mpa(std::max(p[2], p[3])));
  m.set("endplate_time_over_warning_s", s.endplate_over_warning_s);
  m.set("posterior_time_over_warning_s", s.posterior_over_warning_s);
  m.set("bone_peak_load_N", s.peak_load_N);
  m.set("bone_peak_load_time_s", s.peak_load_t_s);
}

}  // namespace acdr
