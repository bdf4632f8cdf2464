// The force a live device feels between two physics steps. When a scene's step costs more than
// the haptic period (the C4-C5 modules, fine boxes), the device loop still runs at 1 kHz on its
// own thread and renders the last physics force corrected for how far the hand has moved since
// that step, through the virtual coupling's own spring:
//   F_hand(t) = F_phys - k_c (x_dev(t) - x_dev(t_phys)),
// a local linear model of the simulation held between its updates (Cavusoglu & Tendick, ICRA
// 2000, "Multirate simulation for high fidelity haptic interaction with deformable objects";
// the coupling spring is the stiffest, passive part of the loop, Colgate et al. 1995). The
// result is limited like the World's own output: clamped to the device's rated maximum, slewed
// at its force-rate limit per haptic tick, and zero while the device data is stale, non-finite,
// or has jumped farther than the device's jump threshold since the physics step.
#pragma once

#include "engine/core/types.hpp"
#include "engine/devices/device_config.hpp"

namespace acdr {

/// What the physics thread hands to the device loop after each step.
struct PhysicsForce {
  Vec3 force_N = Vec3::Zero();          ///< the World's feedback force (already limited)
  Vec3 device_position_m = Vec3::Zero();  ///< device position the step consumed
  bool valid = false;                    ///< false until the first step
};

/// One force for the device per haptic tick.
struct LocalForce {
  Vec3 force_N = Vec3::Zero();
  bool clamped = false;  ///< the magnitude limit was hit
  bool zeroed = false;   ///< stale, non-finite or jumped input: nothing rendered
};

class HapticLocalModel {
 public:
  /// `coupling_stiffness_N_m`: the scenario's coupling spring; `tick_s`: the haptic period.
  HapticLocalModel(const DeviceConfig& device, double coupling_stiffness_N_m, double tick_s);

  /// The force for the device now, from the newest physics output and the newest device
  /// position (`stale`: no fresh device data beyond its silence limit).
  LocalForce force(const PhysicsForce& physics, const Vec3& device_position_m, bool stale);

 private:
  DeviceConfig device_;
  double k_;
  double tick_s_;
  Vec3 last_ = Vec3::Zero();
};

}  // namespace acdr
