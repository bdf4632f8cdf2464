// World assembly and the fixed step.
#include "engine/world/world.hpp"

#include <chrono>
#include <cmath>

#include "engine/core/state_hash.hpp"
#include "engine/rigid/instrument_dynamics.hpp"

namespace acdr {
namespace {

using Clock = std::chrono::steady_clock;

struct StageClock {
  StageTimes& times;
  Clock::time_point last = Clock::now();
  void lap(StepStage s) {
    const auto now = Clock::now();
    times.seconds[static_cast<int>(s)] += std::chrono::duration<double>(now - last).count();
    last = now;
  }
};

/// Whether p lies outside the box [lo, hi] along some axis: a particle there counts as removed
/// (WorldConfig::removal).
inline bool outside_region(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return p.x() < lo.x() || p.y() < lo.y() || p.z() < lo.z() || p.x() > hi.x() ||
         p.y() > hi.y() || p.z() > hi.z();
}

}  // namespace

const char* step_stage_name(StepStage stage) {
  switch (stage) {
    case StepStage::kInput: return "input";
    case StepStage::kNucleus: return "nucleus";
    case StepStage::kInstrument: return "instrument";
    case StepStage::kFeedback: return "feedback";
    case StepStage::kRecord: return "record";
    case StepStage::kCount: break;
  }
  return "?";
}

static_assert(Frame::kZoneCapacity == kMaxZones, "Frame::zones must hold every zone");

World::World(const WorldConfig& config)
    : config_(config), guard_(config.device, config.instrument_start, config.solver.dt_s) {
  static_colliders_ = build_static_colliders(config_.ground, config_.box);
  // anatomy: vertebrae, their distance grid for the particles, the zones
  if (config_.anatomy.enabled) {
    anatomy_ = std::make_unique<Anatomy>(config_.anatomy);
    static_colliders_.push_back(anatomy_->bone_collider());
    for (const DangerZone& z : anatomy_->zones())
      summary_.zones.push_back({z.name, z.warning_distance_m, z.force_limit_N, z.never_event});
    frame_.zone_count = static_cast<std::int32_t>(anatomy_->zones().size());
  }
  if (config_.instrument.enabled) {
    instrument_.emplace(config_.instrument);
    coupling_ = coupling_gains(config_.coupling, config_.instrument.mass_kg,
                               instrument_->principal_inertia().x());
  }
  rigid_ = std::make_unique<RigidWorld>(config_.gravity_m_s2, config_.instrument_start,
                                        instrument_ ? &*instrument_ : nullptr, static_colliders_);
  if (anatomy_) {
    // Bone as static Bullet triangle meshes: the instrument's contacts with it are measured.
    rigid_->add_static_mesh(anatomy_->vertebra(VertebraLevel::kC4));
    rigid_->add_static_mesh(anatomy_->vertebra(VertebraLevel::kC5));
  }
  if (config_.nucleus.enabled)
    nucleus_ = std::make_unique<Nucleus>(config_.nucleus, config_.solver, config_.gravity_m_s2,
                                         static_colliders_);
  if (instrument_) {
    rigid_->place_instrument(config_.instrument_start);
    moving_.reserve(instrument_->local_colliders().size());
    instrument_->world_colliders(config_.instrument_start, Vec3::Zero(), Vec3::Zero(), moving_);
  }
  reactions_.resize(1);
  events_.reserve(4096);
  last_target_orientation_ = config_.instrument_start.orientation;

  summary_.dt_s = config_.solver.dt_s;
  if (nucleus_) {
    summary_.particle_volume_m3 = nucleus_->particle_volume_m3();
    const auto mats = nucleus_->materials();
    for (std::uint8_t m : mats) {
      const bool target = m < config_.nucleus.materials.size() &&
                          config_.nucleus.materials[m].counts_as_target;
      (target ? summary_.initial_target : summary_.initial_protected)++;
    }
  }
  if (instrument_) {
    summary_.yield_moment_Nm = instrument_->yield_moment_Nm();
    summary_.warning_moment_Nm = instrument_->warning_moment_Nm();
  }
  summary_.device_max_force_N = config_.device.max_force_N;
  frame_.device = config_.instrument_start;
  frame_.instrument = config_.instrument_start;
  count_removed();
}

World::~World() = default;

void World::emit(EventKind kind, double value, const char* detail) {
  if (events_.size() < events_.capacity()) events_.push_back(Event{t_, kind, value, detail});
}

// Distances from the instrument (at its new pose, in moving_) to every zone, into the frame;
// events on the rising edge of warning, entry (a never-event zone's entry also emits
// kNeverEvent) and force above the zone's limit while near it.
void World::evaluate_zones_and_emit(const Vec3& tissue_force_N) {
  if (!anatomy_ || !instrument_) return;
  const auto& zones = anatomy_->zones();
  const std::size_t n = zones.size();
  evaluate_zones(zones, moving_, tissue_force_N, std::span<ZoneSample>(zone_samples_.data(), n));
  for (std::size_t i = 0; i < n; ++i) {
    const ZoneSample& s = zone_samples_[i];
    const DangerZone& z = zones[i];
    frame_.zones[i] = {static_cast<float>(s.distance_m), static_cast<float>(s.force_N), s.inside,
                       s.warning};
    const bool over = s.warning && s.force_N > z.force_limit_N;
    auto zone_event = [&](EventKind kind, double value) {
      const std::size_t before = events_.size();
      emit(kind, value, z.name.c_str());
      if (events_.size() > before) events_.back().zone = static_cast<std::int32_t>(i);
    };
    if (s.warning && !zone_warn_active_[i]) zone_event(EventKind::kZoneWarning, s.distance_m);
    if (s.inside && !zone_inside_active_[i]) {
      zone_event(EventKind::kZoneEntry, s.distance_m);
      if (z.never_event) zone_event(EventKind::kNeverEvent, s.distance_m);
    }
    if (over && !zone_force_active_[i]) zone_event(EventKind::kZoneForce, s.force_N);
    zone_warn_active_[i] = s.warning;
    zone_inside_active_[i] = s.inside;
    zone_force_active_[i] = over;
  }
}

void World::drain_events(std::vector<Event>& out) {
  out.insert(out.end(), events_.begin(), events_.end());
  events_.clear();
}

bool World::is_removed(std::size_t i) const {
  return outside_region(nucleus_->positions()[i], config_.removal.min_m, config_.removal.max_m);
}

void World::count_removed() {
  frame_.removed_target = 0;
  frame_.removed_protected = 0;
  if (!nucleus_) return;
  const auto mats = nucleus_->materials();
  const auto x = nucleus_->positions();
  const Vec3 lo = config_.removal.min_m, hi = config_.removal.max_m;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!outside_region(x[i], lo, hi)) continue;  // is_removed(i), the bounds read once
    const bool target = mats[i] < config_.nucleus.materials.size() &&
                        config_.nucleus.materials[mats[i]].counts_as_target;
    (target ? frame_.removed_target : frame_.removed_protected)++;
  }
}

const Frame& World::step(const DeviceSample& sample) {
  const double dt = config_.solver.dt_s;
  StageClock clock{times_};

  // input: filter the device pose into a coupling target.
  // A stale sample (the device went silent) holds the target and zeroes the force; it is
  // recorded once per silence, apart from rejected (NaN, jump) samples.
  const GuardedInput in = sample.stale ? guard_.accept_lost() : guard_.accept(sample.pose);
  if (sample.stale && !input_lost_)
    emit(EventKind::kInputLost, sample.silence_s, "device silent: force zeroed");
  input_lost_ = sample.stale;
  const bool rejected = !in.accepted && !sample.stale;
  if (rejected && !input_rejecting_)
    emit(EventKind::kInputRejected, in.jump_m, in.non_finite ? "non-finite pose" : "pose jump");
  input_rejecting_ = rejected;
  const Vec3 omega_target =
      rotation_between(last_target_orientation_, in.target.orientation) / dt;
  last_target_orientation_ = in.target.orientation;
  clock.lap(StepStage::kInput);

  Vec3 nucleus_force = Vec3::Zero();
  Vec3 nucleus_torque_grip = Vec3::Zero();
  RigidContact contact;
  Vec3 coupling_force = Vec3::Zero();

  if (instrument_) {
    const Pose grip = rigid_->instrument_grip();
    const Vec3 com = rigid_->instrument_com_world();
    const Vec3 v0 = rigid_->instrument_com_velocity();
    const Vec3 w0 = rigid_->instrument_angular_velocity();
    const Vec3 v_grip = v0 + w0.cross(grip.position - com);

    // nucleus: particles step against the instrument at its current pose and velocity.
    instrument_->world_colliders(grip, v_grip, w0, moving_);
    BodyReaction& reaction = reactions_[0];
    reaction = BodyReaction{};
    reaction.reference_point = com;
    if (nucleus_) {
      NumericalReport report;
      nucleus_->step(dt, moving_, reactions_, report);
      frame_.solver_iterations = report.iterations;
      if (!report.ok && !failed_) {
        emit(EventKind::kNumerical, report.residual, report.stage);
        failed_ = true;
      }
    }
    clock.lap(StepStage::kNucleus);

    // instrument: implicit update of the 6-DOF body under coupling, nucleus reaction and
    // gravity (engine/rigid/instrument_dynamics.hpp).
    const double m = config_.instrument.mass_kg;
    InstrumentBodyState body;
    body.mass_kg = m;
    body.inertia_kg_m2 = rigid_->instrument_world_inertia();
    body.com_m = com;
    body.com_velocity_m_s = v0;
    body.angular_velocity_rad_s = w0;
    body.grip = grip;
    CouplingTarget target;
    target.pose = in.target;
    target.velocity_m_s = in.target_velocity;
    target.angular_velocity_rad_s = omega_target;
    const InstrumentUpdate update =
        implicit_instrument_update(body, coupling_, target, reaction, config_.gravity_m_s2, dt);
    contact = rigid_->step(dt, update.force_N, update.torque_Nm);

    nucleus_force = reaction.force_N;
    nucleus_torque_grip =
        reaction.torque_Nm + (reaction.reference_point - grip.position).cross(reaction.force_N);

    // Coupling force on the instrument at the new state (what the user's hand supplies).
    const Pose g1 = rigid_->instrument_grip();
    const Vec3 vg1 = rigid_->instrument_grip_velocity();
    coupling_force = coupling_force_N(coupling_, target, g1, vg1);
    frame_.instrument = g1;
    frame_.tip_m = g1.apply(instrument_->working_point());
    clock.lap(StepStage::kInstrument);

    // Shaft bending moment at the grip: moment of the distal loads (particles, rigid
    // contact, the instrument's weight) about the grip, less its torsion component.
    const Vec3 axis = g1.orientation * Vec3::UnitZ();
    const Vec3 com1 = rigid_->instrument_com_world();
    frame_.bending_moment_Nm = shaft_bending_moment_Nm(
        nucleus_torque_grip + contact.torque_about_grip_Nm +
            (com1 - g1.position).cross(m * config_.gravity_m_s2),
        axis);
    const bool warn = frame_.bending_moment_Nm > summary_.warning_moment_Nm;
    const bool yield = frame_.bending_moment_Nm > summary_.yield_moment_Nm;
    if (warn && !warning_active_)
      emit(EventKind::kOverloadWarning, frame_.bending_moment_Nm, "shaft moment above warning");
    if (yield && !yield_active_)
      emit(EventKind::kOverloadYield, frame_.bending_moment_Nm, "shaft moment above yield");
    warning_active_ = warn;
    yield_active_ = yield;

    // anatomy: danger zones against the instrument at its new pose; the force
    // near a zone is what the instrument presses on tissue (bone contact and nucleus).
    if (anatomy_) {
      instrument_->world_colliders(g1, vg1, rigid_->instrument_angular_velocity(), moving_);
      evaluate_zones_and_emit(contact.force_N + nucleus_force);
    }

    if (!g1.position.allFinite() || !g1.orientation.coeffs().allFinite() ||
        !vg1.allFinite()) {
      if (!failed_) emit(EventKind::kNumerical, 0.0, "instrument");
      failed_ = true;
    }
  } else if (nucleus_) {
    NumericalReport report;
    nucleus_->step(dt, {}, {}, report);
    if (!report.ok && !failed_) {
      emit(EventKind::kNumerical, report.residual, report.stage);
      failed_ = true;
    }
    rigid_->step(dt, Vec3::Zero(), Vec3::Zero());
    clock.lap(StepStage::kNucleus);
  }

  // feedback: the user feels the reaction of the coupling, limited for the device.
  const GuardedForce out = guard_.limit(-coupling_force, t_ + dt);
  if (out.clamped && !clamp_active_)
    emit(EventKind::kForceClamped, out.requested_N, "force above device maximum");
  clamp_active_ = out.clamped;
  clock.lap(StepStage::kFeedback);

  // record.
  t_ += dt;
  ++steps_;
  frame_.t_s = t_;
  frame_.device = in.target;
  frame_.input_valid = in.accepted;
  frame_.coupling_force_N = coupling_force;
  frame_.feedback_force_N = out.force_N;
  frame_.nucleus_force_N = nucleus_force;
  frame_.contact_force_N = contact.force_N;
  if (nucleus_) {
    frame_.broken_bonds = static_cast<std::int32_t>(nucleus_->broken_bond_count());
    frame_.active_particles = static_cast<std::int32_t>(nucleus_->active_count());
    count_removed();
  }
  clock.lap(StepStage::kRecord);
  ++times_.steps;
  return frame_;
}

std::uint64_t World::state_hash() const {
  std::uint64_t h = nucleus_ ? nucleus_->state_hash() : kFnvOffset;
  if (rigid_->has_instrument()) {
    const Pose g = rigid_->instrument_grip();
    h = fnv1a(g.position.data(), sizeof(double) * 3, h);
    h = fnv1a(g.orientation.coeffs().data(), sizeof(double) * 4, h);
  }
  return h;
}

}  // namespace acdr
