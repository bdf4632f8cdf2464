// Everything an attempt produced that assessment reads: the world's summary figures, the frame
// stream and the events. Saved as a recording, so any attempt can be re-scored later.
#pragma once

#include <vector>

#include "engine/core/frame.hpp"
#include "engine/world/world.hpp"

namespace acdr {

struct AttemptRecording {
  WorldSummary summary;
  std::vector<Frame> frames;
  std::vector<Event> events;
};

}  // namespace acdr
