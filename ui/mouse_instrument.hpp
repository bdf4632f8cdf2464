// Mouse and keyboard as the instrument's input device when no haptic device is connected.
// The window's thread turns pointer drags, the wheel and held keys into the pose the grip is
// to reach (apply_mouse_input); the haptic thread's device (MouseInstrumentDevice) moves the
// grip toward it at a bounded speed, so a fast flick, or a slow window that sees a whole drag
// in one frame, moves the instrument smoothly and loses nothing. The speeds count simulated
// seconds when the view gives the device the attempt's clock (count_time_by), so a scoop is
// the same scoop on a machine that runs the simulation in slow motion. The mapping (docs/trainee-view.md), shown on screen by the HUD:
//   left-drag          move the instrument in the horizontal plane, relative to the view
//                      (drag right: to the screen's right; drag up: away from the viewer)
//   wheel              depth: forward (away from you) pushes the instrument in (down),
//                      back draws it out, 0.5 mm a notch
//   right-drag         depth, following the pointer: drag down = deeper, up = out
//   Ctrl + left-drag   turn the instrument: up/down tilts the blade about the view's
//                      horizontal axis (levers it), left/right rolls it about the depth axis
//   W / S              raise / lower the instrument (Shift: three times faster)
//   Q / E, A / D       tilt, roll (as Ctrl + left-drag)
//   Space              hold still (ignore the mouse while held)
//   F                  close a rongeur's jaws while held (its grip; other instruments ignore it)
//   T                  take the next instrument on the tray (with the one in hand out of the disc)
// "Depth" is the world's vertical: every bundled module has the surgeon above the work,
// looking down into it. The grip follows at most 20 mm/s and 2 rad/s (of simulated time when
// the view gives it the attempt's clock; a drag cannot teleport the instrument, and the device
// guard would reject a jump anyway).
#pragma once

#include <functional>
#include <mutex>

#include "engine/devices/input_device.hpp"
#include "ui/render_scene.hpp"

namespace acdr {

/// A device whose goal pose is set by another thread (the window's); the haptic thread's
/// samples move toward it at a bounded speed.
class MouseInstrumentDevice final : public InputDevice {
 public:
  struct Speeds {
    double max_speed_m_s = 0.02;
    double max_turn_rad_s = 2.0;
  };
  explicit MouseInstrumentDevice(const Pose& start) : MouseInstrumentDevice(start, Speeds{}) {}
  MouseInstrumentDevice(const Pose& start, const Speeds& speeds)
      : goal_(start), pose_(start), speeds_(speeds) {}

  /// Window thread: the pose to reach from now on.
  void set_pose(const Pose& goal);
  /// The pose to reach (what the window's input moves).
  Pose pose() const;
  /// Where the grip is (the last sample's pose).
  Pose current() const;
  /// Window thread: how far the hand closes the instrument's jaws, 0 open .. 1 closed.
  void set_grip(double grip);
  /// Window thread: ask for the next instrument on the tray (T; the simulation exchanges it
  /// once the one in hand is out of the disc).
  void next_instrument();
  /// Window thread: the trainee has finished (the attempt ends at the next step).
  void request_end();
  /// The clock the speeds are counted in (seconds): the simulation's, so that the grip moves
  /// 20 mm per simulated second however slowly the machine steps it (at 0.25x real time a
  /// clock on the wall would let it cover 80 mm per simulated second, and the scoop would
  /// be a different, faster one). Empty: the time each sample is given (the device loop's).
  void count_time_by(std::function<double()> clock);

  bool sample(double t_s, DeviceSample& out) override;
  bool live() const override { return true; }

 private:
  mutable std::mutex mutex_;  ///< held only to copy or step a pose
  Pose goal_;
  Pose pose_;
  Speeds speeds_;
  std::function<double()> clock_;
  double last_t_s_ = -1.0;
  double grip_ = 0.0;
  int instrument_presses_ = 0;
  bool end_ = false;
};

/// What the pointer and keyboard did in one window frame.
struct MouseKeyInput {
  float drag_dx_px = 0.0f;  ///< left-button drag this frame (pixels, +x right)
  float drag_dy_px = 0.0f;  ///< (+y down, as on screen)
  float depth_drag_px = 0.0f;  ///< right-button drag, vertical (+ down on screen = deeper)
  float wheel_notches = 0.0f;  ///< + forward (away from the user) = deeper
  float turn_dx_px = 0.0f;     ///< Ctrl + left drag: roll (+ right)
  float turn_dy_px = 0.0f;     ///< tilt (+ down)
  bool up = false, down = false;             ///< W, S
  bool tilt_plus = false, tilt_minus = false;  ///< E, Q
  bool roll_plus = false, roll_minus = false;  ///< D, A
  bool fast = false;                         ///< Shift
  bool hold = false;                         ///< Space
  double dt_s = 1.0 / 60.0;                  ///< frame time
};

struct MouseMapping {
  double metres_per_px = 0.1e-3;      ///< drag scale: 0.1 mm per pixel
  double depth_per_notch_m = 0.5e-3;  ///< wheel: 0.5 mm a notch
  double depth_per_px_m = 0.1e-3;     ///< right-drag: 0.1 mm per pixel
  double turn_per_px_rad = 0.005;     ///< Ctrl + drag: 0.29 degrees per pixel
  double vertical_speed_m_s = 0.02;   ///< W/S speed (x3 with Shift)
  double turn_speed_rad_s = 0.8;      ///< Q/E, A/D
  double max_step_m = 0.03;           ///< the most one frame may move the goal
  double max_turn_rad = 0.5;          ///< the most one frame may turn it
};

/// The grip pose after one frame of input, moving relative to `camera`'s view.
Pose apply_mouse_input(const Pose& current, const MouseKeyInput& input, const RenderCamera& camera,
                       const MouseMapping& mapping = {});

}  // namespace acdr
