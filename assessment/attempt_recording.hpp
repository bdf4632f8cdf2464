// Everything an attempt produced that assessment reads: the world's summary figures, the frame
// stream and the events. Saved as a recording, so any attempt can be re-scored later.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "engine/core/bone_load.hpp"
#include "engine/core/frame.hpp"
#include "engine/world/world.hpp"

namespace acdr {

struct AttemptRecording {
  WorldSummary summary;
  std::vector<Frame> frames;
  std::vector<Event> events;
  /// The loads on the bone, sampled at the bone model's rate (empty when it is off).
  std::vector<BoneLoadRecord> bone_loads;
  /// Where the removed particles lie at the end of the attempt (m), in particle order: what
  /// the lump metrics read. Absent from checkpoints of a running attempt and from recordings
  /// made before it was kept (those have no lump metrics).
  std::optional<std::vector<Eigen::Vector3f>> removed_positions;
};

}  // namespace acdr
