// The rigid world in Bullet: ground plane, the open box's five static walls, bone meshes, and
// the instrument as a dynamic body. Bullet resolves the instrument's contact with walls and bone;
// the contact force on the instrument is measured from the solver's impulses.
#pragma once

#include <memory>

#include "engine/core/bone_load.hpp"
#include "engine/geometry/collider.hpp"
#include "engine/geometry/triangle_mesh.hpp"
#include "engine/rigid/instrument.hpp"
#include "engine/rigid/instrument_config.hpp"

namespace acdr {

/// Contact of the instrument with static geometry in the last step.
struct RigidContact {
  Vec3 force_N = Vec3::Zero();           ///< total contact force on the instrument
  Vec3 torque_about_grip_Nm = Vec3::Zero();
  double peak_point_force_N = 0.0;       ///< largest single contact point force
  int points = 0;
};

class RigidWorld {
 public:
  /// Builds only the declared parts. `static_colliders` are the same solids the particles see.
  /// `instrument_start` is the grip pose the instrument starts at (at rest).
  RigidWorld(const Vec3& gravity_m_s2, const Pose& instrument_start,
             const InstrumentGeometry* instrument, const std::vector<Collider>& static_colliders);
  ~RigidWorld();
  RigidWorld(const RigidWorld&) = delete;
  RigidWorld& operator=(const RigidWorld&) = delete;

  bool has_instrument() const;
  /// Grip pose and velocities (of the grip point) of the instrument.
  Pose instrument_grip() const;
  Vec3 instrument_grip_velocity() const;
  Vec3 instrument_angular_velocity() const;
  /// Velocity of the centre of mass.
  Vec3 instrument_com_velocity() const;
  Vec3 instrument_com_world() const;
  /// World inertia tensor about the centre of mass.
  Eigen::Matrix3d instrument_world_inertia() const;

  /// Applies a force and torque (about the centre of mass) for the next step and advances the
  /// world by dt; returns the contact the instrument made.
  RigidContact step(double dt, const Vec3& force_N, const Vec3& torque_Nm);

  /// Moves part `index` of the instrument (its local collider of that index) to a new pose in
  /// the body frame, for parts that move on the body (a rongeur's jaws).
  void set_instrument_part(int index, const Pose& local);

  /// Adds another instrument's shape (built now, so an exchange allocates none); returns its
  /// index for exchange_instrument. The instrument of the constructor is index 0.
  int add_instrument_shape(const InstrumentGeometry& instrument);
  /// Puts instrument `index`'s shape and mass in the hand: the grip keeps its pose and
  /// velocities, the old shape's contacts are dropped.
  void exchange_instrument(int index);

  /// Places the instrument (grip pose) at rest, e.g. at the start.
  void place_instrument(const Pose& grip);

  /// Adds a static closed triangle mesh (bone, world frame) as a Bullet BVH triangle mesh with
  /// a 0.1 mm margin (built in millimetres, see rigid_world.cpp). The mesh is copied.
  void add_static_mesh(const TriangleMesh& mesh);

  /// Appends to `out` the instrument's contact points with the static meshes in the last
  /// step (mesh k, in the order added, as `vertebra` k): the point on the mesh and the force
  /// the instrument put on it, from the impulses of a step of `dt`. Reads the contact state
  /// only; points beyond the sample's capacity are counted in `out.dropped`.
  void gather_mesh_contacts(double dt, BoneLoadSample& out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace acdr
