// Bullet soft-body peer of the nucleus (see bullet_peer.hpp for the configuration).
#include "bench/bullet_peer.hpp"

#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "bench/run_loop.hpp"
#include "engine/anatomy/anatomy.hpp"
#include "engine/rigid/instrument.hpp"
#include "engine/nucleus/nucleus.hpp"
#include "engine/rigid/rigid_world.hpp"

namespace acdr {
namespace {

constexpr double kMm = 1000.0;  // metres -> world units (mm)
constexpr double kInstrumentMass = 1000.0;  // kg: contact impulses barely move it

// Collision groups: statics and the instrument touch only the soft body.
constexpr int kGroupStatic = 1;
constexpr int kGroupSoft = 2;
constexpr int kGroupInstrument = 4;

btVector3 to_bt(const Vec3& v, double scale = kMm) {
  return btVector3(v.x() * scale, v.y() * scale, v.z() * scale);
}
btTransform to_bt(const Pose& p) {
  const Quat& q = p.orientation;
  return btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), to_bt(p.position));
}

/// A Bullet shape for one of our colliders (world units mm), or null when it has no convex
/// counterpart here: the bone's distance grid (kSdfGrid) is built from the anatomy's meshes
/// instead (bone_mesh_shape). The cup shell has no Bullet counterpart; it becomes the sphere
/// around it (said so in docs/performance.md).
btCollisionShape* make_shape(const Collider& c) {
  btCollisionShape* s = nullptr;
  switch (c.kind) {
    case ColliderKind::kSdfGrid: return nullptr;
    case ColliderKind::kBox: s = new btBoxShape(to_bt(c.half_extents_m)); break;
    case ColliderKind::kCapsule:
      s = new btCapsuleShapeZ(c.radius_m * kMm, 2.0 * c.half_length_m * kMm);
      break;
    case ColliderKind::kCupShell: s = new btSphereShape(c.radius_m * kMm); break;
    case ColliderKind::kHalfSpace: s = new btStaticPlaneShape(btVector3(0, 0, 1), 0.0); break;
  }
  s->setMargin(0.01);
  return s;
}

/// Static triangle-mesh shape of one vertebra, in millimetres (the peer's world unit, where
/// Bullet's 0.002-unit BVH box floor is 2 um; the rigid world builds its bone meshes in
/// millimetres for the same reason, engine/rigid/rigid_world.cpp). `vertices` and `indices` must
/// outlive the shape.
struct BoneMesh {
  std::vector<btScalar> vertices;
  std::vector<int> indices;
  std::unique_ptr<btTriangleIndexVertexArray> array;
  std::unique_ptr<btBvhTriangleMeshShape> shape;
};

std::unique_ptr<BoneMesh> bone_mesh_shape(const TriangleMesh& mesh) {
  auto out = std::make_unique<BoneMesh>();
  out->vertices.reserve(3 * mesh.vertices.size());
  for (const Vec3& v : mesh.vertices)
    for (int k = 0; k < 3; ++k) out->vertices.push_back(static_cast<btScalar>(v[k] * kMm));
  out->indices.reserve(3 * mesh.triangles.size());
  for (const auto& t : mesh.triangles)
    for (std::uint32_t i : t) out->indices.push_back(static_cast<int>(i));
  out->array = std::make_unique<btTriangleIndexVertexArray>(
      static_cast<int>(mesh.triangles.size()), out->indices.data(),
      static_cast<int>(3 * sizeof(int)), static_cast<int>(mesh.vertices.size()),
      out->vertices.data(), static_cast<int>(3 * sizeof(btScalar)));
  out->shape = std::make_unique<btBvhTriangleMeshShape>(out->array.get(), true);
  out->shape->setMargin(0.01);
  return out;
}

}  // namespace

RunTrace run_bullet_peer(const WorldConfig& config, const Pose& start,
                         const std::vector<Pose>& path, const RunWindow& window,
                         const PeerSettings& settings,
                         const std::function<void(double)>& progress) {
  RunTrace out;
  const double dt = settings.dt_s;

  // The same lattice and bonds as our nucleus: build one and read them back. With anatomy the
  // lattice is filled around the bone's distance grid, as in the World.
  std::vector<Collider> statics = build_static_colliders(config.ground, config.box);
  std::unique_ptr<Anatomy> anatomy;
  if (config.anatomy.enabled) {
    anatomy = std::make_unique<Anatomy>(config.anatomy);
    statics.push_back(anatomy->bone_collider());
  }
  const Nucleus lattice(config.nucleus, config.solver, config.gravity_m_s2, statics);
  const std::size_t n = lattice.particle_count();
  const auto x0 = lattice.positions();
  const auto masses = lattice.masses();
  const auto bonds = lattice.bond_particles();
  out.particles = n;
  out.bonds = lattice.bond_count();

  // World.
  auto collision_config = std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>();
  auto dispatcher = std::make_unique<btCollisionDispatcher>(collision_config.get());
  auto broadphase = std::make_unique<btDbvtBroadphase>();
  auto solver = std::make_unique<btSequentialImpulseConstraintSolver>();
  auto world = std::make_unique<btSoftRigidDynamicsWorld>(dispatcher.get(), broadphase.get(),
                                                          solver.get(), collision_config.get());
  const btVector3 gravity = to_bt(config.gravity_m_s2);
  world->setGravity(gravity);
  btSoftBodyWorldInfo& info = world->getWorldInfo();
  info.m_gravity = gravity;
  info.m_dispatcher = dispatcher.get();
  info.m_broadphase = broadphase.get();
  info.air_density = 0.0;
  info.water_density = 0.0;
  info.m_sparsesdf.Initialize();
  info.m_sparsesdf.setDefaultVoxelsz(0.25);  // mm
  info.m_sparsesdf.Reset();

  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btRigidBody>> bodies;
  std::vector<std::unique_ptr<btMotionState>> motions;
  std::vector<std::unique_ptr<BoneMesh>> bone;
  for (const Collider& c : statics) {
    btCollisionShape* shape = make_shape(c);
    if (!shape) continue;  // the bone: its meshes below
    shapes.emplace_back(shape);
    Pose p = c.pose;
    motions.emplace_back(new btDefaultMotionState(to_bt(p)));
    btRigidBody::btRigidBodyConstructionInfo ci(0.0, motions.back().get(), shapes.back().get());
    bodies.emplace_back(new btRigidBody(ci));
    world->addRigidBody(bodies.back().get(), kGroupStatic, kGroupSoft);
  }

  // Bone: both vertebrae as static BVH triangle meshes. The soft body meets them through
  // Bullet's soft-concave algorithm (a per-triangle convex shape and sparse distance field).
  if (anatomy) {
    for (VertebraLevel level : {VertebraLevel::kC4, VertebraLevel::kC5}) {
      bone.push_back(bone_mesh_shape(anatomy->vertebra(level)));
      motions.emplace_back(new btDefaultMotionState(btTransform::getIdentity()));
      btRigidBody::btRigidBodyConstructionInfo ci(0.0, motions.back().get(),
                                                  bone.back()->shape.get());
      bodies.emplace_back(new btRigidBody(ci));
      world->addRigidBody(bodies.back().get(), kGroupStatic, kGroupSoft);
    }
  }

  // Instrument: a compound of its colliders, heavy, no gravity, touching only the soft body.
  btRigidBody* instrument = nullptr;
  if (config.instrument.enabled) {
    const InstrumentGeometry geometry(config.instrument);
    auto* compound = new btCompoundShape();
    shapes.emplace_back(compound);
    for (const Collider& c : geometry.local_colliders()) {
      btCollisionShape* shape = make_shape(c);
      if (!shape) continue;
      shapes.emplace_back(shape);
      compound->addChildShape(to_bt(c.pose), shapes.back().get());
    }
    btVector3 inertia(0, 0, 0);
    compound->calculateLocalInertia(kInstrumentMass, inertia);
    motions.emplace_back(new btDefaultMotionState(to_bt(start)));
    btRigidBody::btRigidBodyConstructionInfo ci(kInstrumentMass, motions.back().get(), compound,
                                                inertia);
    bodies.emplace_back(new btRigidBody(ci));
    instrument = bodies.back().get();
    instrument->setActivationState(DISABLE_DEACTIVATION);
    world->addRigidBody(instrument, kGroupInstrument, kGroupSoft);
    instrument->setGravity(btVector3(0, 0, 0));
    instrument->setDamping(0.0, 0.0);
  }

  // Soft body: margin first (nodes take the margin in force when they are added).
  auto soft = std::make_unique<btSoftBody>(&info);
  // The node-less constructor makes no material; nodes take material 0.
  soft->getCollisionShape()->setMargin(0.5 * lattice.spacing_m() * kMm);
  btSoftBody::Material* material = soft->appendMaterial();
  for (std::size_t i = 0; i < n; ++i) soft->appendNode(to_bt(x0[i]), masses[i]);
  material->m_kLST = settings.link_stiffness;
  material->m_kAST = 1.0;
  material->m_kVST = 1.0;
  for (std::size_t b = 0; b < lattice.bond_count(); ++b)
    soft->appendLink(bonds[2 * b], bonds[2 * b + 1], material, false);
  soft->m_cfg.piterations = std::max(1, settings.position_iterations);
  soft->m_cfg.kDP = settings.damping;
  soft->m_cfg.collisions = btSoftBody::fCollision::SDF_RS;
  soft->setActivationState(DISABLE_DEACTIVATION);
  world->addSoftBody(soft.get(), kGroupSoft, kGroupStatic | kGroupInstrument);

  // Step: the instrument is placed on the path with the path's velocity, the world steps, and
  // the force on the instrument is its momentum change from the contact impulses.
  const double duration =
      window.duration_s > 0.0 ? window.duration_s
                              : window.sample_s * static_cast<double>(path.size());
  run_timed_loop(
      duration, dt, window, out,
      [&](std::int64_t k) {
        LoopStep step;
        if (instrument) {
          const PathMotion m = motion_on_path(start, path, window.sample_s, double(k) * dt, dt);
          const btTransform tr = to_bt(m.pose);
          instrument->setWorldTransform(tr);
          instrument->getMotionState()->setWorldTransform(tr);
          instrument->setInterpolationWorldTransform(tr);
          const btVector3 v_bt = to_bt(m.velocity_m_s);
          const Vec3& w = m.angular_velocity_rad_s;
          const btVector3 w_bt(w.x(), w.y(), w.z());
          instrument->setLinearVelocity(v_bt);
          instrument->setAngularVelocity(w_bt);
          instrument->setInterpolationLinearVelocity(v_bt);
          instrument->setInterpolationAngularVelocity(w_bt);
          world->stepSimulation(dt, 0, dt);
          // Momentum change from the contact impulses (kg mm/s per step -> N).
          const btVector3 dv = instrument->getLinearVelocity() - v_bt;
          step.force_N = Vec3(dv.x(), dv.y(), dv.z()) * (kInstrumentMass / dt / kMm);
        } else {
          world->stepSimulation(dt, 0, dt);
        }
        info.m_sparsesdf.GarbageCollect();
        step.instrument = pose_on_path(start, path, window.sample_s, double(k + 1) * dt);
        // A blown-up soft body stops the run (a sample of its nodes is checked).
        bool finite = true;
        for (int i = 0; i < soft->m_nodes.size() && finite; i += 97)
          finite = std::isfinite(soft->m_nodes[i].m_x.x());
        step.stop = !finite;
        if (!finite) out.failed = true;
        return step;
      },
      progress);
  // A failed run still counts the whole window (its point is marked failed).
  out.steps = run_step_count(duration, dt);
  out.sim_s = double(out.steps) * dt;

  // Removed: nodes outside the removal region at the end.
  std::int32_t removed = 0, target = 0;
  const auto mats = lattice.materials();
  for (std::size_t i = 0; i < n; ++i) {
    const bool is_target = mats[i] < config.nucleus.materials.size()
                               ? config.nucleus.materials[mats[i]].counts_as_target
                               : true;
    if (!is_target) continue;
    ++target;
    const btVector3& p = soft->m_nodes[static_cast<int>(i)].m_x;
    const Vec3 x(p.x() / kMm, p.y() / kMm, p.z() / kMm);
    const auto& r = config.removal;
    if ((x.array() < r.min_m.array()).any() || (x.array() > r.max_m.array()).any()) ++removed;
  }
  out.removed_target = removed;
  out.removed_fraction = target > 0 ? double(removed) / target : 0.0;

  world->removeSoftBody(soft.get());
  for (auto& b : bodies) world->removeRigidBody(b.get());
  return out;
}

}  // namespace acdr
