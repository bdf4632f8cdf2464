// The bone metrics of a stored attempt, computed again from its recording's load samples:
// the scenario's anatomy and bone model are built once (meshes from the cache) and every
// sample is solved in order, as the attempt's worker thread did (bone_stress_worker.hpp), so
// the metrics come out the same bit for bit.
#pragma once

#include <memory>
#include <string>

#include "assessment/attempt_recording.hpp"
#include "assessment/attempt_result.hpp"
#include "engine/bone/bone_segment.hpp"
#include "scenarios/scenario_model.hpp"

namespace acdr {

class BoneMetricsReplay {
 public:
  BoneMetricsReplay();
  ~BoneMetricsReplay();
  /// Appends the bone metrics of `record` to `metrics` when `scenario` models the bone (does
  /// nothing otherwise). A recording without bone samples (from before the bone was modelled)
  /// gets none either. Returns false with `error` set when the bone cannot be built.
  bool add_metrics(const ScenarioModel& scenario, const AttemptRecording& record,
                   Metrics& metrics, std::string* error);

  /// The bone built for `scenario` (built on first use; null with `error` on failure).
  const BoneSegment* bone(const ScenarioModel& scenario, std::string* error);

 private:
  std::string hash_;  // the scenario the models below belong to
  std::unique_ptr<Anatomy> anatomy_;
  std::unique_ptr<BoneSegment> bone_;
};

}  // namespace acdr
