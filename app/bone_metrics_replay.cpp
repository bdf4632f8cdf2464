// Re-computing the bone metrics from a recording: see bone_metrics_replay.hpp.
#include "app/bone_metrics_replay.hpp"

#include <exception>

#include "assessment/bone_metrics.hpp"
#include "engine/bone/bone_stress_history.hpp"

namespace acdr {

BoneMetricsReplay::BoneMetricsReplay() = default;
BoneMetricsReplay::~BoneMetricsReplay() = default;

const BoneSegment* BoneMetricsReplay::bone(const ScenarioModel& scenario, std::string* error) {
  const std::string key = scenario.path + "#" + scenario.hash;
  if (bone_ && hash_ == key) return bone_.get();
  bone_.reset();
  anatomy_.reset();
  hash_ = key;
  try {
    anatomy_ = std::make_unique<Anatomy>(scenario.world.anatomy);
  } catch (const std::exception& e) {
    if (error) *error = e.what();
    return nullptr;
  }
  bone_ = BoneSegment::build(*anatomy_, scenario.bone,
                             anatomy_cache_dir(scenario.world.anatomy, "bone"), error);
  return bone_.get();
}

bool BoneMetricsReplay::add_metrics(const ScenarioModel& scenario, const AttemptRecording& record,
                                    Metrics& metrics, std::string* error) {
  if (!scenario.bone.enabled || record.bone_loads.empty()) return true;
  const BoneSegment* segment = bone(scenario, error);
  if (!segment) return false;
  add_bone_metrics(analyse_bone_loads(*segment, record.bone_loads), metrics);
  return true;
}

}  // namespace acdr
