// Names of engine events, as stored in recordings and shown to users.
#include "engine/core/frame.hpp"

namespace acdr {

const char* event_kind_name(EventKind kind) {
  switch (kind) {
    case EventKind::kNumerical: return "numerical";
    case EventKind::kOverloadWarning: return "overload_warning";
    case EventKind::kOverloadYield: return "overload_yield";
    case EventKind::kInputRejected: return "input_rejected";
    case EventKind::kForceClamped: return "force_clamped";
    case EventKind::kAttemptEnd: return "attempt_end";
    case EventKind::kInputLost: return "input_lost";
    case EventKind::kDeviceDisconnected: return "device_disconnected";
    case EventKind::kZoneWarning: return "zone_warning";
    case EventKind::kZoneEntry: return "zone_entry";
    case EventKind::kNeverEvent: return "never_event";
    case EventKind::kZoneForce: return "zone_force";
    case EventKind::kInstrumentExchange: return "instrument_exchange";
  }
  return "unknown";
}

int instrument_in_hand(std::span<const Event> events, double t_s) {
  int in_hand = 0;
  for (const Event& e : events) {
    if (e.t_s > t_s) break;
    if (e.kind == EventKind::kInstrumentExchange) in_hand = static_cast<int>(e.value);
  }
  return in_hand;
}

}  // namespace acdr
