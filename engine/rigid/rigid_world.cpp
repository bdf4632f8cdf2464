// Bullet rigid world at millimetre scale, in double precision (docs/dependencies.md: the single-precision
// build misplaces contacts at this scale; default margins of 0.04 units are far too large).
#include "engine/rigid/rigid_world.hpp"

#include <btBulletDynamicsCommon.h>

#include <vector>

namespace acdr {
namespace {

constexpr double kMargin = 1.0e-4;  // 0.1 mm collision margin for every convex shape

btVector3 to_bt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }
Vec3 from_bt(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }
btQuaternion to_bt(const Quat& q) { return btQuaternion(q.x(), q.y(), q.z(), q.w()); }
Quat from_bt(const btQuaternion& q) { return Quat(q.w(), q.x(), q.y(), q.z()); }

// The force a contact point's last impulses (normal and both friction directions) put on the
// manifold's body A (`on_a`) or B over a step of dt, N. normalWorldOnB points from B to A; the
// impulse pushes A along it.
Vec3 contact_force_on(const btManifoldPoint& pt, bool on_a, double dt) {
  Vec3 f = from_bt(pt.m_normalWorldOnB) * pt.getAppliedImpulse() +
           from_bt(pt.m_lateralFrictionDir1) * pt.m_appliedImpulseLateral1 +
           from_bt(pt.m_lateralFrictionDir2) * pt.m_appliedImpulseLateral2;
  f /= dt;
  return on_a ? f : Vec3(-f);
}
btTransform to_bt(const Pose& p) { return btTransform(to_bt(p.orientation), to_bt(p.position)); }

// One instrument as Bullet sees it: its compound shape (children about the centre of mass),
// the centre of mass in the grip frame, mass and principal inertia.
struct InstrumentShapeData {
  std::unique_ptr<btCompoundShape> compound;
  Vec3 com = Vec3::Zero();
  double mass = 0.0;
  Vec3 inertia = Vec3::Zero();
};

}  // namespace

struct RigidWorld::Impl {
  btDefaultCollisionConfiguration collision_config;
  btCollisionDispatcher dispatcher{&collision_config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld world{&dispatcher, &broadphase, &solver, &collision_config};

  // Bone meshes, declared before the shapes that read them so they outlive them:
  // vertex and index copies in millimetres, their arrays, the unscaled BVH shapes.
  std::vector<std::vector<btScalar>> mesh_vertices;
  std::vector<std::vector<int>> mesh_indices;
  std::vector<std::unique_ptr<btTriangleIndexVertexArray>> mesh_arrays;
  std::vector<std::unique_ptr<btBvhTriangleMeshShape>> mesh_shapes;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btRigidBody>> statics;
  // Every instrument's compound shape and mass properties (the exchange swaps them on the one
  // body); the shape in hand.
  std::vector<InstrumentShapeData> instrument_shapes;
  btCompoundShape* instrument_shape = nullptr;
  std::unique_ptr<btRigidBody> instrument;
  std::unique_ptr<btDefaultMotionState> instrument_motion;
  Pose com_in_grip;  // centre-of-mass frame relative to the grip frame (translation only)

  void add_static(std::unique_ptr<btCollisionShape> shape, const btTransform& xf) {
    btRigidBody::btRigidBodyConstructionInfo info(0.0, nullptr, shape.get());
    info.m_startWorldTransform = xf;
    info.m_friction = 0.3;
    auto body = std::make_unique<btRigidBody>(info);
    body->setUserIndex2(-1);  // not a mesh (add_static_mesh numbers its meshes)
    world.addRigidBody(body.get());
    statics.push_back(std::move(body));
    shapes.push_back(std::move(shape));
  }
};

RigidWorld::RigidWorld(const Vec3& gravity_m_s2, const Pose& instrument_start,
                       const InstrumentGeometry* instrument,
                       const std::vector<Collider>& static_colliders)
    : impl_(std::make_unique<Impl>()) {
  auto& w = impl_->world;
  w.setGravity(to_bt(gravity_m_s2));
  w.getSolverInfo().m_numIterations = 20;
  // Penetration is pushed out by split impulses (a position-level correction that adds no
  // momentum) from 10 um on. Bullet's default threshold, -0.04, is in world units and assumes
  // metre-sized bodies: here it would be 40 mm, so every overlap of the millimetre instrument
  // would be corrected with velocity-level (Baumgarte) impulses, which count as contact force:
  // a shaft pinned between the endplate rims would show 8-19 N m "bending moments" that no
  // force in the scene applies (the coupling can apply ~1 N m).
  w.getSolverInfo().m_splitImpulse = 1;
  w.getSolverInfo().m_splitImpulsePenetrationThreshold = -1.0e-5;

  for (const Collider& c : static_colliders) {
    if (c.particles_only) continue;
    if (c.kind == ColliderKind::kHalfSpace) {
      auto plane = std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0.0);
      plane->setMargin(kMargin);
      impl_->add_static(std::move(plane), to_bt(c.pose));
    } else if (c.kind == ColliderKind::kBox) {
      auto box = std::make_unique<btBoxShape>(to_bt(c.half_extents_m));
      box->setMargin(kMargin);
      impl_->add_static(std::move(box), to_bt(c.pose));
    }
  }

  if (instrument) {
    const int k = add_instrument_shape(*instrument);
    const InstrumentShapeData& shape = impl_->instrument_shapes[static_cast<std::size_t>(k)];
    impl_->com_in_grip.position = shape.com;
    impl_->instrument_motion = std::make_unique<btDefaultMotionState>(
        to_bt(Pose{instrument_start.apply(shape.com), instrument_start.orientation}));
    btRigidBody::btRigidBodyConstructionInfo info(shape.mass, impl_->instrument_motion.get(),
                                                  shape.compound.get(), to_bt(shape.inertia));
    info.m_friction = 0.3;
    impl_->instrument = std::make_unique<btRigidBody>(info);
    impl_->instrument->setActivationState(DISABLE_DEACTIVATION);
    impl_->instrument->setDamping(0.0, 0.0);
    // Gravity is applied together with the coupling, in the instrument's implicit update
    // (instrument_dynamics.hpp).
    impl_->instrument->setFlags(impl_->instrument->getFlags() | BT_DISABLE_WORLD_GRAVITY);
    impl_->instrument->setGravity(btVector3(0, 0, 0));
    // Continuous collision: the blade is 2 mm thick and may move 1 mm per step.
    impl_->instrument->setCcdMotionThreshold(5e-4);
    impl_->instrument->setCcdSweptSphereRadius(2e-4);
    impl_->instrument_shape = shape.compound.get();
    w.addRigidBody(impl_->instrument.get());
  }
}

int RigidWorld::add_instrument_shape(const InstrumentGeometry& instrument) {
  InstrumentShapeData data;
  data.com = instrument.center_of_mass();
  data.mass = instrument.config().mass_kg;
  data.inertia = instrument.principal_inertia();
  data.compound = std::make_unique<btCompoundShape>();
  for (const Collider& c : instrument.local_colliders()) {
    std::unique_ptr<btCollisionShape> shape;
    if (c.kind == ColliderKind::kBox) {
      shape = std::make_unique<btBoxShape>(to_bt(c.half_extents_m));
    } else if (c.kind == ColliderKind::kCapsule) {
      shape = std::make_unique<btCapsuleShapeZ>(c.radius_m, 2.0 * c.half_length_m);
    } else if (c.kind == ColliderKind::kCupShell) {
      // Bullet sees the cup as its convex hull (a hemisphere), enough for bone contact.
      auto hull = std::make_unique<btConvexHullShape>();
      const int rings = 6, segments = 16;
      for (int i = 0; i <= rings; ++i) {
        const double polar = 0.5 * SIMD_PI * i / rings;  // 0 at the bottom pole
        for (int j = 0; j < segments; ++j) {
          const double az = 2.0 * SIMD_PI * j / segments;
          hull->addPoint(btVector3(c.radius_m * std::sin(polar) * std::cos(az),
                                   c.radius_m * std::sin(polar) * std::sin(az),
                                   -c.radius_m * std::cos(polar)),
                         false);
        }
      }
      // The hull caches its box with the margin it has when the box is computed; with the
      // default 0.04 (40 mm here) every query against bone returns thousands of triangles
      // (300 ms per step on the anatomy scene). So the margin is set first.
      hull->setMargin(kMargin);
      hull->recalcLocalAabb();
      shape = std::move(hull);
    } else {
      continue;
    }
    shape->setMargin(kMargin);
    Pose local = c.pose;
    local.position -= data.com;  // child transforms relative to the centre of mass
    data.compound->addChildShape(to_bt(local), shape.get());
    impl_->shapes.push_back(std::move(shape));
  }
  data.compound->setMargin(kMargin);
  impl_->instrument_shapes.push_back(std::move(data));
  return static_cast<int>(impl_->instrument_shapes.size()) - 1;
}

void RigidWorld::exchange_instrument(int index) {
  auto* body = impl_->instrument.get();
  const InstrumentShapeData& shape = impl_->instrument_shapes.at(static_cast<std::size_t>(index));
  if (!body || shape.compound.get() == impl_->instrument_shape) return;
  // The grip keeps its pose and velocities: the hand holds the new instrument where it held
  // the old one.
  const Pose grip = instrument_grip();
  const Vec3 v_grip = instrument_grip_velocity();
  const Vec3 omega = instrument_angular_velocity();
  auto& w = impl_->world;
  // Contacts of the old shape go with it (their manifolds name its children).
  w.getBroadphase()->getOverlappingPairCache()->cleanProxyFromPairs(body->getBroadphaseHandle(),
                                                                    w.getDispatcher());
  body->setCollisionShape(shape.compound.get());
  body->setMassProps(shape.mass, to_bt(shape.inertia));
  impl_->instrument_shape = shape.compound.get();
  impl_->com_in_grip.position = shape.com;
  const btTransform xf = to_bt(Pose{grip.apply(shape.com), grip.orientation});
  body->setWorldTransform(xf);
  body->setInterpolationWorldTransform(xf);
  if (body->getMotionState()) body->getMotionState()->setWorldTransform(xf);
  body->updateInertiaTensor();
  const Vec3 v_com = v_grip + omega.cross(Vec3(grip.orientation * shape.com));
  body->setLinearVelocity(to_bt(v_com));
  body->setAngularVelocity(to_bt(omega));
  body->setInterpolationLinearVelocity(to_bt(v_com));
  body->setInterpolationAngularVelocity(to_bt(omega));
  body->clearForces();
  w.updateSingleAabb(body);
}

RigidWorld::~RigidWorld() {
  if (impl_->instrument) impl_->world.removeRigidBody(impl_->instrument.get());
  for (auto& b : impl_->statics) impl_->world.removeRigidBody(b.get());
}

bool RigidWorld::has_instrument() const { return impl_->instrument != nullptr; }

void RigidWorld::set_instrument_part(int index, const Pose& local) {
  Pose relative = local;
  relative.position -= impl_->com_in_grip.position;  // child transforms are about the centre of mass
  impl_->instrument_shape->updateChildTransform(index, to_bt(relative), true);
}

Pose RigidWorld::instrument_grip() const {
  const btTransform& xf = impl_->instrument->getWorldTransform();
  Pose com{from_bt(xf.getOrigin()), from_bt(xf.getRotation())};
  Pose grip;
  grip.orientation = com.orientation;
  grip.position = com.position - com.orientation * impl_->com_in_grip.position;
  return grip;
}

Vec3 RigidWorld::instrument_com_world() const {
  return from_bt(impl_->instrument->getWorldTransform().getOrigin());
}

Vec3 RigidWorld::instrument_com_velocity() const {
  return from_bt(impl_->instrument->getLinearVelocity());
}

Vec3 RigidWorld::instrument_angular_velocity() const {
  return from_bt(impl_->instrument->getAngularVelocity());
}

Vec3 RigidWorld::instrument_grip_velocity() const {
  const Vec3 omega = instrument_angular_velocity();
  return instrument_com_velocity() + omega.cross(instrument_grip().position - instrument_com_world());
}

Eigen::Matrix3d RigidWorld::instrument_world_inertia() const {
  const btMatrix3x3 inv = impl_->instrument->getInvInertiaTensorWorld();
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = inv[r][c];
  return m.inverse();
}

void RigidWorld::place_instrument(const Pose& grip) {
  auto* body = impl_->instrument.get();
  const btTransform xf = to_bt(Pose{grip.apply(impl_->com_in_grip.position), grip.orientation});
  body->setWorldTransform(xf);
  body->setInterpolationWorldTransform(xf);
  if (body->getMotionState()) body->getMotionState()->setWorldTransform(xf);
  body->setLinearVelocity(btVector3(0, 0, 0));
  body->setAngularVelocity(btVector3(0, 0, 0));
  body->clearForces();
}

void RigidWorld::add_static_mesh(const TriangleMesh& mesh) {
  // Bullet's BVH grows every triangle's box to at least 0.002 units a side (btOptimizedBvh,
  // MIN_AABB_DIMENSION), i.e. 2 mm in this metre world: every query would then return hundreds
  // of the bone's sub-millimetre triangles (measured: 300 ms per step). So the BVH is built in
  // millimetres and scaled back by btScaledBvhTriangleMeshShape, where that floor is 2 um.
  constexpr double kUnitsPerMetre = 1000.0;
  auto& vertices = impl_->mesh_vertices.emplace_back();
  vertices.reserve(3 * mesh.vertices.size());
  for (const Vec3& v : mesh.vertices)
    for (int k = 0; k < 3; ++k) vertices.push_back(static_cast<btScalar>(v[k] * kUnitsPerMetre));
  auto& indices = impl_->mesh_indices.emplace_back();
  indices.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    for (std::uint32_t i : t) indices.push_back(static_cast<int>(i));
  auto array = std::make_unique<btTriangleIndexVertexArray>(
      static_cast<int>(mesh.triangles.size()), indices.data(), static_cast<int>(3 * sizeof(int)),
      static_cast<int>(mesh.vertices.size()), vertices.data(), static_cast<int>(3 * sizeof(btScalar)));
  auto bvh = std::make_unique<btBvhTriangleMeshShape>(array.get(), true);
  bvh->setMargin(kMargin * kUnitsPerMetre);
  auto shape = std::make_unique<btScaledBvhTriangleMeshShape>(
      bvh.get(), btVector3(1.0 / kUnitsPerMetre, 1.0 / kUnitsPerMetre, 1.0 / kUnitsPerMetre));
  shape->setMargin(kMargin);
  impl_->add_static(std::move(shape), btTransform::getIdentity());
  // Which mesh a contact is with (gather_mesh_contacts); Bullet does not read the index.
  impl_->statics.back()->setUserIndex2(static_cast<int>(impl_->mesh_shapes.size()));
  impl_->mesh_arrays.push_back(std::move(array));
  impl_->mesh_shapes.push_back(std::move(bvh));
}

RigidContact RigidWorld::step(double dt, const Vec3& force_N, const Vec3& torque_Nm) {
  RigidContact contact;
  auto* body = impl_->instrument.get();
  if (body) {
    body->clearForces();
    body->applyCentralForce(to_bt(force_N));
    body->applyTorque(to_bt(torque_Nm));
  }
  // One fixed internal step of exactly dt (maxSubSteps = 0 means "step by dt").
  impl_->world.stepSimulation(dt, 0, dt);
  if (!body) return contact;

  // Sum the impulses the solver applied at the instrument's contact points.
  const Vec3 grip = instrument_grip().position;
  auto* dispatcher = impl_->world.getDispatcher();
  for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
    btPersistentManifold* manifold = dispatcher->getManifoldByIndexInternal(m);
    const bool is_a = manifold->getBody0() == body;
    const bool is_b = manifold->getBody1() == body;
    if (!is_a && !is_b) continue;
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      const btManifoldPoint& pt = manifold->getContactPoint(p);
      if (pt.getDistance() > 1e-4) continue;
      const Vec3 f = contact_force_on(pt, is_a, dt);
      const Vec3 at = from_bt(is_a ? pt.getPositionWorldOnA() : pt.getPositionWorldOnB());
      contact.force_N += f;
      contact.torque_about_grip_Nm += (at - grip).cross(f);
      contact.peak_point_force_N = std::max(contact.peak_point_force_N, f.norm());
      ++contact.points;
    }
  }
  return contact;
}

void RigidWorld::gather_mesh_contacts(double dt, BoneLoadSample& out) const {
  const auto* body = impl_->instrument.get();
  if (!body || !(dt > 0.0)) return;
  const auto* dispatcher = impl_->world.getDispatcher();
  for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
    const btPersistentManifold* manifold =
        const_cast<btDispatcher*>(dispatcher)->getManifoldByIndexInternal(m);
    const bool is_a = manifold->getBody0() == body;
    const bool is_b = manifold->getBody1() == body;
    if (!is_a && !is_b) continue;
    const btCollisionObject* other = is_a ? manifold->getBody1() : manifold->getBody0();
    const int mesh = other->getUserIndex2();
    if (mesh < 0) continue;  // not a mesh (ground, box walls)
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      const btManifoldPoint& pt = manifold->getContactPoint(p);
      if (pt.getDistance() > 1e-4) continue;
      // The same force step() sums on the instrument; the mesh feels its opposite.
      const Vec3 f = contact_force_on(pt, is_a, dt);
      if (f.squaredNorm() == 0.0) continue;
      if (out.count >= BoneLoadSample::kCapacity) {
        ++out.dropped;
        continue;
      }
      BoneLoadPoint& load = out.points[out.count++];
      load.point_m =
          from_bt(is_a ? pt.getPositionWorldOnB() : pt.getPositionWorldOnA()).cast<float>();
      load.force_N = (-f).cast<float>();
      load.radius_m = 0.0f;  // the bone model's default contact patch
      load.vertebra = static_cast<std::uint8_t>(mesh);
      load.source = BoneLoadSource::kInstrument;
    }
  }
}

}  // namespace acdr
