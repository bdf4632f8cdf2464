// What a scene says about the hand instrument and the virtual coupling that drives it from the
// device pose (plain data, SI units).
#pragma once

#include <numbers>
#include <string>

#include "engine/core/types.hpp"

namespace acdr {

enum class InstrumentShape { kPrism, kCupCurette, kRongeur };

/// The hand instrument. Its body frame has its origin at the grip point G (where the device
/// holds it); the shaft runs from G along local -z to the working tip T = (0, 0, -shaft_length).
struct InstrumentConfig {
  bool enabled = false;
  /// What the trainee and the record call it when a scene has several (WorldConfig::instruments).
  std::string name;
  InstrumentShape shape = InstrumentShape::kPrism;
  double mass_kg = 0.03;
  double shaft_length_m = 0.08;     ///< grip to working tip
  double shaft_diameter_m = 2.0e-3; ///< round shaft; sets the yield moment
  double yield_stress_Pa = 500e6;   ///< surgical stainless steel, scenario-editable
  double warning_fraction = 0.5;    ///< moment above this fraction of yield is an overload warning
  /// Prism blade (seed Fig. 4-6): length along local x, width along y, height along z; its
  /// lower face is at the tip.
  Vec3 blade_size_m = Vec3(8.0e-3, 4.0e-3, 10.0e-3);
  double cup_diameter_m = 4.0e-3;   ///< cup curette: inner diameter of the cup
  double cup_depth_m = 2.0e-3;      ///< cup curette: depth of the cup
  double cup_wall_m = 0.4e-3;       ///< cup curette: wall thickness
  /// Cup curette: angle between the shaft's direction toward the tip and the cup's opening,
  /// rad. pi/2 opens sideways (a straight curette); larger angles turn the opening back toward
  /// the handle, as on an angled (reverse) curette, so a pull stroke loads the cup's floor.
  double cup_opening_angle_rad = 0.5 * std::numbers::pi;
  /// Pituitary rongeur: two cup jaws hinged at the shaft's tip, opening in the body x-z plane
  /// (one jaw toward +x, the other toward -x), each a plate of `jaw_wall_m` whose inner face
  /// stands `jaw_depth_m` off the shaft axis when closed, so closed jaws enclose a space
  /// 2 depth x width x length. Straight cervical rongeurs have 2-4 mm jaws (docs/anatomy.md).
  double jaw_length_m = 6.0e-3;    ///< from the hinge at the tip to the jaw's end, along -z
  double jaw_width_m = 3.0e-3;     ///< across the jaw, along body y
  double jaw_depth_m = 1.0e-3;     ///< each jaw's cup depth: axis to its inner face, closed
  double jaw_wall_m = 0.4e-3;      ///< jaw plate thickness
  double jaw_opening_rad = 50.0 * std::numbers::pi / 180.0;  ///< angle between open jaws
  /// Angled jaws: the jaws' axis (the line their closed faces meet on) bent at the hinge off
  /// the shaft's axis toward body +x, in the plane they open in, rad; 0 straight. Up-angled
  /// ("up-biting") pituitary rongeurs are bent 15-45 deg (docs/anatomy.md); turning the shaft
  /// about its axis turns the bend with it.
  double jaw_angle_rad = 0.0;
  double jaw_close_time_s = 0.2;   ///< fastest full closing or opening by the hand
  /// Closure at and above which the jaws hold what is between them, and at and below which
  /// they let it go (the gap between the two keeps a grip from flickering).
  double jaw_hold_closure = 0.9;
  double jaw_release_closure = 0.5;
  /// Open jaws (at or below jaw_release_closure), and opening ones, whose plates are both
  /// outside the removal region are shaken off over the tray: the gel slides on them
  /// (Collider::slip) instead of clinging to them by its no-slip coupling, so what lies on the
  /// plates falls off.
  bool jaw_shake_off = true;

  bool has_jaws() const { return shape == InstrumentShape::kRongeur; }
  /// Bending moment at which the shaft yields: M_yield = sigma_y * pi * d^3 / 32.
  double yield_moment_Nm() const;
};

/// Virtual coupling between the device pose and the instrument (Colgate 1995; Adams &
/// Hannaford 1999). Critical damping is kd = 2*sqrt(m*ks).
struct CouplingConfig {
  double stiffness_N_m = 500.0;       ///< below the Phantom Omni's 700 N/m (docs/references.md)
  double damping_Ns_m = -1.0;         ///< < 0: critically damped from mass and stiffness
  double rot_stiffness_Nm_rad = 0.5;
  double rot_damping_Nms_rad = -1.0;  ///< < 0: critically damped from inertia
};

}  // namespace acdr
