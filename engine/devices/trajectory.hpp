// A recorded device trajectory: grip poses over time, read from and written to CSV, and
// played back as an input device.
//
// CSV format (docs/trajectory-format.md): '#' comment lines, then a header line
//   t_s,x_m,y_m,z_m,qw,qx,qy,qz[,grip][,instrument]
// then one sample per line: decimal numbers only, the first time >= 0 and times strictly
// increasing, quaternions of any finite non-zero scale normalised on load; the optional grip
// (0 open .. 1 closed) closes an instrument's jaws; the optional instrument (an index into the
// scene's instruments, held from its sample to the next) picks the instrument in hand.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engine/devices/input_device.hpp"
#include "engine/core/types.hpp"

namespace acdr {

struct TrajectorySample {
  double t_s = 0.0;
  Pose pose;
  double grip = 0.0;  ///< jaw closure the hand asks for, 0 open .. 1 closed
  int instrument = -1;  ///< the instrument the hand asks for (DeviceSample::instrument)
};

class Trajectory {
 public:
  Trajectory() = default;
  /// `has_grip`: the samples' grip values are meant (written as the grip column).
  /// `has_instrument`: so are their instrument values (the instrument column).
  explicit Trajectory(std::vector<TrajectorySample> samples, bool has_grip = false,
                      bool has_instrument = false);

  /// Loads a CSV trajectory. On failure returns nullopt and sets `error` to
  /// "file:line: what is wrong (got X, expected Y)".
  static std::optional<Trajectory> load_csv(const std::string& path, std::string* error);
  /// Parses CSV text; `name` is used in error messages.
  static std::optional<Trajectory> parse_csv(const std::string& text, const std::string& name,
                                             std::string* error);
  bool save_csv(const std::string& path, std::string* error) const;

  /// Pose at time t: linear in position, spherical-linear in orientation, held at the ends.
  Pose at(double t_s) const;
  /// Grip at time t: linear between samples, held at the ends (0 without a grip column).
  double grip_at(double t_s) const;
  /// Whether the trajectory carries a grip column.
  bool has_grip() const { return has_grip_; }
  /// The instrument asked for at time t: that of the last sample at or before t (the first
  /// sample's before it; -1 without an instrument column).
  int instrument_at(double t_s) const;
  /// Whether the trajectory carries an instrument column, and the largest index it asks for.
  bool has_instrument() const { return has_instrument_; }
  int max_instrument() const;
  double duration_s() const { return samples_.empty() ? 0.0 : samples_.back().t_s; }
  const std::vector<TrajectorySample>& samples() const { return samples_; }

 private:
  /// For t strictly inside the samples' span: the index of the first sample later than t and
  /// the fraction of the way to it from the one before.
  std::pair<std::size_t, double> segment(double t_s) const;

  std::vector<TrajectorySample> samples_;
  bool has_grip_ = false;
  bool has_instrument_ = false;
};

/// The rotation of [w, x, y, z] as a unit quaternion, for any finite, non-zero scale (a scaled
/// quaternion means the same rotation); nullopt for zero or non-finite components.
std::optional<Quat> unit_quaternion(double w, double x, double y, double z);

/// Plays a trajectory as a device; reports `end` once the last sample's time has passed.
class TrajectoryReplay final : public InputDevice {
 public:
  explicit TrajectoryReplay(Trajectory trajectory) : trajectory_(std::move(trajectory)) {}
  bool sample(double t_s, DeviceSample& out) override;

 private:
  Trajectory trajectory_;
};

}  // namespace acdr
