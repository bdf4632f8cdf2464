// Mouse and keyboard as the instrument's input device when no haptic device is connected.
// The window's thread turns pointer drags and held keys into a grip pose (apply_mouse_input);
// the haptic thread reads the newest pose as its device sample (MouseInstrumentDevice). The
// mapping (docs/trainee-view.md):
//   left-drag          move the instrument in the horizontal plane, relative to the view
//                      (drag right: to the screen's right; drag up: away from the viewer)
//   W / S              raise / lower the instrument (Shift: three times faster)
//   Q / E              tilt the instrument about the view's horizontal axis (lever the blade)
//   A / D              roll it about the view's depth axis
//   Space              hold still (ignore the mouse while held)
// Moves are speed-limited (a drag cannot teleport the instrument): the device guard would
// reject a jump anyway.
#pragma once

#include <mutex>

#include "engine/devices/input_device.hpp"
#include "ui/render_scene.hpp"

namespace acdr {

/// A device whose pose is set by another thread (the window's), read by the haptic thread.
class MouseInstrumentDevice final : public InputDevice {
 public:
  explicit MouseInstrumentDevice(const Pose& start) : pose_(start) {}

  /// Window thread: the pose to follow from now on.
  void set_pose(const Pose& pose);
  Pose pose() const;
  /// Window thread: the trainee has finished (the attempt ends at the next step).
  void request_end();

  bool sample(double t_s, DeviceSample& out) override;
  bool live() const override { return true; }

 private:
  mutable std::mutex mutex_;  ///< held only to copy a pose
  Pose pose_;
  bool end_ = false;
};

/// What the pointer and keyboard did in one window frame.
struct MouseKeyInput {
  float drag_dx_px = 0.0f;  ///< left-button drag this frame (pixels, +x right)
  float drag_dy_px = 0.0f;  ///< (+y down, as on screen)
  bool up = false, down = false;             ///< W, S
  bool tilt_plus = false, tilt_minus = false;  ///< E, Q
  bool roll_plus = false, roll_minus = false;  ///< D, A
  bool fast = false;                         ///< Shift
  bool hold = false;                         ///< Space
  double dt_s = 1.0 / 60.0;                  ///< frame time
};

struct MouseMapping {
  double metres_per_px = 0.1e-3;    ///< drag scale: 0.1 mm per pixel
  double vertical_speed_m_s = 0.02; ///< W/S speed (x3 with Shift)
  double turn_speed_rad_s = 0.8;    ///< Q/E, A/D
  double max_step_m = 4.0e-3;       ///< the most one frame may move the grip
};

/// The grip pose after one frame of input, moving relative to `camera`'s view.
Pose apply_mouse_input(const Pose& current, const MouseKeyInput& input, const RenderCamera& camera,
                       const MouseMapping& mapping = {});

}  // namespace acdr
