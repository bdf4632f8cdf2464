// A source of device poses: a recorded trajectory, the mouse, or a UDP haptic bridge.
#pragma once

#include <cstdint>

#include "engine/core/types.hpp"

namespace acdr {

/// One device reading at simulated time t.
struct DeviceSample {
  double t_s = 0.0;
  Pose pose;                 ///< grip pose, world frame
  std::uint32_t buttons = 0;
  /// How far the hand closes the instrument's jaws, 0 open .. 1 closed (a rongeur; other
  /// instruments ignore it): a trajectory's grip column, a bridge's first button.
  double grip = 0.0;
  /// The instrument the hand asks for, an index into WorldConfig::instruments taken modulo
  /// their number (a trajectory's instrument column; the count of presses of the bridge's
  /// second button or of T in mouse mode); -1 keeps the one in hand. The World exchanges it
  /// only once the one in hand is outside the disc.
  int instrument = -1;
  bool end = false;          ///< the source has finished (end of trajectory, end-of-attempt)
  /// No fresh data for longer than the device's silence limit (e.g. UDP packets lost): the pose
  /// is held and the force goes to zero until data returns (DeviceGuard::accept_lost).
  bool stale = false;
  /// The device has been silent past its disconnect timeout: the attempt ends.
  bool disconnected = false;
  double silence_s = 0.0;  ///< time since the device's last fresh data (s), when it knows
};

/// The interface the step loop reads from. One virtual call per step, never per particle.
class InputDevice {
 public:
  virtual ~InputDevice() = default;
  /// The pose to follow at simulated time t_s. Returns false when no new sample is available
  /// (the previous one stays in force).
  virtual bool sample(double t_s, DeviceSample& out) = 0;
  /// Receives the force the simulation renders back to the user (N), after clamping.
  virtual void render_force(const Vec3& force_N) {}
  /// The attempt is over (`reason` in words): a device may tell its bridge or user. Called
  /// once, after the last step.
  virtual void finish(const char* reason) {}
  /// A live device (a hand on it: a haptic bridge, the mouse) rather than a recording: it
  /// gets its own 1 kHz loop when the attempt runs live (app/live_attempt.hpp).
  virtual bool live() const { return false; }
};

}  // namespace acdr
