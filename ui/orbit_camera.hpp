// A camera the user turns around a target point: yaw and pitch about the vertical (+z), a
// distance, and panning of the target. Starts from any RenderCamera (e.g. the default framing
// of the work area) and gives one back for the renderer.
#pragma once

#include "ui/render_scene.hpp"

namespace acdr {

class OrbitCamera {
 public:
  OrbitCamera() = default;
  /// Takes target, distance and angles from `camera` (its eye around its target).
  explicit OrbitCamera(const RenderCamera& camera) { reset(camera); }
  void reset(const RenderCamera& camera);

  /// Turns by pixel deltas of a drag (`rad_per_px` per pixel). Pitch stays within ±85°.
  void orbit(float dx_px, float dy_px, float rad_per_px = 0.006f);
  /// Sets the direction the eye looks from, keeping the distance and the target: `yaw_rad`
  /// about the vertical (0: from -y, looking along +y), `pitch_rad` the elevation above the
  /// target's horizontal plane (within ±85°).
  void set_angles(float yaw_rad, float pitch_rad);
  /// Zooms by wheel notches: each notch moves 12 % closer (positive) or farther.
  void zoom(float notches);
  /// Moves the target in the view plane by pixel deltas of a drag, in a viewport of height
  /// `viewport_height_px`, so a dragged point stays under the pointer.
  void pan(float dx_px, float dy_px, float viewport_height_px);

  RenderCamera camera() const;
  float yaw() const { return yaw_; }
  float pitch() const { return pitch_; }
  float distance() const { return distance_; }
  const Eigen::Vector3f& target() const { return target_; }

 private:
  RenderCamera base_;
  Eigen::Vector3f target_ = Eigen::Vector3f::Zero();
  float yaw_ = 0.0f;     ///< rad, about +z, 0 looking along +y
  float pitch_ = 0.5f;   ///< rad, elevation of the eye above the target's horizontal plane
  float distance_ = 0.1f;
};

}  // namespace acdr
