// Everything an attempt produced that assessment reads: the world's summary figures, the frame
// stream and the events. Saved as a recording, so any attempt can be re-scored later.
#pragma once

#include <vector>

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
};

}  // namespace acdr
