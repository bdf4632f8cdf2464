// What the engine emits each step: a frame of instrument state and forces, and events.
// Assessment works only on these (never on live engine internals), so a recording of frames
// and events is enough to re-score an attempt.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>

#include "engine/core/types.hpp"

namespace acdr {

/// One fixed step's outcome. Forces in N, moments in N·m, positions in m.
struct Frame {
  double t_s = 0.0;
  Pose device;                     ///< commanded grip pose (after input filtering)
  Pose instrument;                 ///< simulated grip pose
  Vec3 tip_m = Vec3::Zero();       ///< working tip position
  Vec3 coupling_force_N = Vec3::Zero();  ///< virtual-coupling force on the instrument
  Vec3 feedback_force_N = Vec3::Zero();  ///< force sent to the device (clamped, rate limited)
  Vec3 nucleus_force_N = Vec3::Zero();   ///< reaction of the particles on the instrument
  Vec3 contact_force_N = Vec3::Zero();   ///< rigid contact (walls, bone) on the instrument
  double bending_moment_Nm = 0.0;  ///< shaft bending moment at the grip
  std::int32_t removed_target = 0;    ///< particles of target material removed so far
  std::int32_t removed_protected = 0; ///< particles of non-target material removed so far
  std::int32_t broken_bonds = 0;      ///< bonds broken so far
  std::int32_t active_particles = 0;  ///< particles integrated this step (not asleep)
  std::int32_t solver_iterations = 0;  ///< linear solver iterations this step (0 between multi-rate particle steps)
  bool input_valid = true;            ///< false when the device sample was rejected
  // anatomy: one sample per danger zone, fixed capacity (no allocation)
  struct ZoneState {
    float distance_m = 0.0f;  ///< closest instrument-zone distance, negative overlapping
    float force_N = 0.0f;     ///< instrument force while within the warning distance, else 0
    bool inside = false;      ///< overlapping the zone
    bool warning = false;     ///< within the zone's warning distance
  };
  static constexpr int kZoneCapacity = 16;  ///< = kMaxZones (world_config.hpp)
  std::int32_t zone_count = 0;               ///< zones of the scene (WorldSummary::zones)
  std::array<ZoneState, kZoneCapacity> zones{};
};

enum class EventKind : std::uint8_t {
  kNumerical = 0,      ///< NaN/Inf or a blow-up, with the stage in `detail`
  kOverloadWarning,    ///< bending moment crossed the warning fraction of yield (value: moment)
  kOverloadYield,      ///< bending moment crossed the yield moment: instrument bent
  kInputRejected,      ///< device sample with NaN or a jump, ignored (value: jump in m)
  kForceClamped,       ///< feedback force limited to the device maximum (value: requested N)
  kAttemptEnd,
  kInputLost,          ///< device silent beyond its silence limit: pose held, force zeroed
                       ///< (value: silence in s)
  kDeviceDisconnected, ///< device silent beyond its disconnect timeout: the attempt ends
                       ///< (value: silence in s)
  // --- anatomy; `zone` names the zone index, `detail` its name ---
  kZoneWarning,        ///< instrument came within a zone's warning distance (value: distance m)
  kZoneEntry,          ///< instrument overlapped a zone (value: distance m, negative)
  kNeverEvent,         ///< entry into a never-event zone: the attempt fails (value: distance m)
  kZoneForce,          ///< force near a zone rose above its limit (value: force N)
  /// The hand took another instrument from the tray (value: its index among
  /// WorldConfig::instruments, `detail` its name).
  kInstrumentExchange,
};

/// The highest EventKind value (readers of stored events reject larger ones).
inline constexpr EventKind kLastEventKind = EventKind::kInstrumentExchange;

const char* event_kind_name(EventKind kind);

struct Event {
  double t_s = 0.0;
  EventKind kind = EventKind::kNumerical;
  double value = 0.0;
  std::string detail;
  std::int32_t zone = -1;  ///< zone index for zone events, else -1
};

/// The place on the tray of the instrument in hand at t_s after `events` (in time order): that
/// of the last instrument exchange at or before t_s; 0, the tray's first, before any.
int instrument_in_hand(std::span<const Event> events, double t_s);

}  // namespace acdr
