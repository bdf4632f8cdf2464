// World assembly and the fixed step.
#include "engine/world/world.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <span>

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
    : config_(config),
      guard_(config.device, config.instrument_start, config.solver.dt_s),
      nucleus_every_(std::max(1, config.solver.nucleus_every)) {
  static_colliders_ = build_static_colliders(config_.ground, config_.box);
  // anatomy: vertebrae, their distance grid for the particles, the zones
  if (config_.anatomy.enabled) {
    anatomy_ = std::make_unique<Anatomy>(config_.anatomy);
    // The ligament's face half a lattice spacing behind the bodies: the disc's particles stand
    // for cells h wide around the lattice sites, so its back row's cells reach that far.
    if (config_.anatomy.posterior_ligament && config_.nucleus.enabled)
      static_colliders_.push_back(
          anatomy_->posterior_ligament_collider(0.5 * config_.nucleus.spacing_m));
    static_colliders_.push_back(anatomy_->bone_collider());  // last: its loads are gathered
    for (const DangerZone& z : anatomy_->zones())
      summary_.zones.push_back({z.name, z.warning_distance_m, z.force_limit_N, z.never_event});
    frame_.zone_count = static_cast<std::int32_t>(anatomy_->zones().size());
  }
  if (config_.instrument.enabled) {
    if (config_.instruments.empty()) {
      tray_.emplace_back(config_.instrument);
    } else {
      tray_.reserve(config_.instruments.size());
      for (const InstrumentConfig& ic : config_.instruments) tray_.emplace_back(ic);
    }
    instrument_ = &tray_.front();
    coupling_ = coupling_gains(config_.coupling, instrument_->config().mass_kg,
                               instrument_->principal_inertia().x());
  }
  rigid_ = std::make_unique<RigidWorld>(config_.gravity_m_s2, config_.instrument_start,
                                        instrument_, static_colliders_);
  for (std::size_t k = 1; k < tray_.size(); ++k) rigid_->add_instrument_shape(tray_[k]);
  if (anatomy_) {
    // Bone as static Bullet triangle meshes: the instrument's contacts with it are measured.
    rigid_->add_static_mesh(anatomy_->vertebra(VertebraLevel::kC4));
    rigid_->add_static_mesh(anatomy_->vertebra(VertebraLevel::kC5));
  }
  if (anatomy_ && config_.anatomy.bone_load_period_s > 0.0) {
    bone_period_steps_ = std::max<std::int64_t>(
        1, std::llround(config_.anatomy.bone_load_period_s / config_.solver.dt_s));
  }
  if (config_.nucleus.enabled) {
    NucleusOptions options;
    // The bone (the last static collider) when its loads are sampled.
    if (bone_period_steps_ > 0) options.gathered_static = static_cast<int>(static_colliders_.size()) - 1;
    // The particles' own step (their solver's tolerance is scaled by it).
    SolverConfig solver = config_.solver;
    solver.dt_s = nucleus_dt_s();
    nucleus_ = std::make_unique<Nucleus>(config_.nucleus, solver, config_.gravity_m_s2,
                                         static_colliders_, options);
  }
  const bool any_jaws = std::any_of(tray_.begin(), tray_.end(), [](const InstrumentGeometry& g) {
    return g.config().has_jaws();
  });
  if (instrument_ && nucleus_ && any_jaws) {
    // The jaws can hold at most every particle: the lists never grow inside a step.
    held_.reserve(nucleus_->particle_count());
    held_local_.reserve(nucleus_->particle_count());
  }
  if (instrument_) {
    rigid_->place_instrument(config_.instrument_start);
    std::size_t most = 0;  // colliders of the largest instrument: an exchange never allocates
    for (const InstrumentGeometry& g : tray_) most = std::max(most, g.local_colliders().size());
    moving_.reserve(most);
    if (config_.solver.nucleus_pipelined) particle_moving_.reserve(most);
    instrument_->world_colliders(config_.instrument_start, Vec3::Zero(), Vec3::Zero(), moving_);
  }
  reactions_.resize(1);
  particle_reactions_.resize(1);
  if (nucleus_ && config_.solver.nucleus_pipelined) {
    particle_worker_ = std::make_unique<StepWorker>([this] { run_particle_step(); },
                                                    config_.solver.nucleus_thread);
    nucleus_->reserve_rows_ahead();
    const auto x = nucleus_->positions();
    handed_on_x_.assign(x.begin(), x.end());
  }
  // An event's text is a zone's or an instrument's name or one of the step's own messages
  // (all under 64 characters): every slot keeps room for the longest, so emitting allocates
  // nothing.
  std::size_t text = 64;
  if (anatomy_)
    for (const DangerZone& z : anatomy_->zones()) text = std::max(text, z.name.size());
  for (const InstrumentGeometry& g : tray_) text = std::max(text, g.config().name.size());
  events_.resize(kMaxPendingEvents);
  for (Event& e : events_) e.detail.reserve(text);
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

// What one step's stages hand on to the next.
struct World::StepData {
  GuardedInput input;                    // the device sample after the guard
  CouplingTarget target;                 // where the coupling pulls the grip
  Vec3 nucleus_force_N = Vec3::Zero();   // the particles' force on the instrument
  RigidContact contact;                  // the instrument's contact with static solids
  Vec3 coupling_force_N = Vec3::Zero();  // the coupling's force on the instrument, new state
  GuardedForce feedback;                 // the force the device renders
};

const Frame& World::step(const DeviceSample& sample) {
  StageClock clock{times_};
  StepData s;
  read_input(sample, s);
  clock.lap(StepStage::kInput);
  step_nucleus();
  clock.lap(StepStage::kNucleus);
  step_instrument(s);
  clock.lap(StepStage::kInstrument);
  send_feedback(s);
  clock.lap(StepStage::kFeedback);
  record(s);
  clock.lap(StepStage::kRecord);
  prepare_nucleus();
  clock.lap(StepStage::kNucleus);
  ++times_.steps;
  return frame_;
}

// input: the guard filters the device pose into the coupling's target. A stale sample (the
// device went silent) holds the target and zeroes the force; it is recorded once per silence,
// apart from rejected (NaN, jump) samples.
void World::read_input(const DeviceSample& sample, StepData& s) {
  const GuardedInput in = sample.stale ? guard_.accept_lost() : guard_.accept(sample.pose);
  if (sample.stale && !input_lost_)
    emit(EventKind::kInputLost, sample.silence_s, "device silent: force zeroed");
  input_lost_ = sample.stale;
  const bool rejected = !in.accepted && !sample.stale;
  if (rejected && !input_rejecting_)
    emit(EventKind::kInputRejected, in.jump_m, in.non_finite ? "non-finite pose" : "pose jump");
  input_rejecting_ = rejected;

  s.input = in;
  s.target.pose = in.target;
  s.target.velocity_m_s = in.target_velocity;
  s.target.angular_velocity_rad_s =
      rotation_between(last_target_orientation_, in.target.orientation) / config_.solver.dt_s;
  last_target_orientation_ = in.target.orientation;
  if (!instrument_) return;
  // Modulo the tray: a device counting presses of a button walks through it.
  if (sample.instrument >= 0 && !sample.stale)
    requested_instrument_ = sample.instrument % static_cast<int>(tray_.size());
  if (requested_instrument_ != instrument_index_) exchange_instrument_when_out();
  if (instrument_->config().has_jaws()) update_jaws(sample);
}

// Whether the instrument in hand is out of the disc: its head (every part but the shaft, the
// last collider; a rongeur's jaws where they stand), the shaft's tip and the working point all
// outside the removal region.
bool World::instrument_outside_region() const {
  const Vec3 lo = config_.removal.min_m, hi = config_.removal.max_m;
  const Pose grip = rigid_->instrument_grip();
  const InstrumentGeometry& g = *instrument_;
  const auto& parts = g.local_colliders();
  const bool jaws = g.config().has_jaws();
  for (std::size_t k = 0; k + 1 < parts.size(); ++k) {
    const Vec3 local = jaws && k < static_cast<std::size_t>(InstrumentGeometry::kJawCount)
                           ? g.jaw_pose(static_cast<int>(k), jaw_closure_).position
                           : parts[k].pose.position;
    if (!outside_region(grip.apply(local), lo, hi)) return false;
  }
  return outside_region(grip.apply(Vec3(0, 0, -g.config().shaft_length_m)), lo, hi) &&
         outside_region(grip.apply(g.working_point()), lo, hi);
}

// The hand puts the instrument down and takes the one it asked for, once the one in hand is
// out of the disc and holds nothing (a rongeur is emptied first). The new one is held where
// the old one was, moving as it moved; a rongeur comes open; the particles' cached sums
// against the old shapes are dropped, and their reaction starts afresh at the next step.
void World::exchange_instrument_when_out() {
  if (!held_.empty() || !instrument_outside_region()) return;
  instrument_index_ = requested_instrument_;
  instrument_ = &tray_[static_cast<std::size_t>(instrument_index_)];
  rigid_->exchange_instrument(instrument_index_);
  coupling_ = coupling_gains(config_.coupling, instrument_->config().mass_kg,
                             instrument_->principal_inertia().x());
  jaw_closure_ = 0.0;
  jaw_rate_ = 0.0;
  jaws_were_closed_ = false;
  if (instrument_->config().has_jaws())
    for (int k = 0; k < InstrumentGeometry::kJawCount; ++k)
      rigid_->set_instrument_part(k, instrument_->jaw_pose(k, 0.0));
  const Pose grip = rigid_->instrument_grip();
  const Vec3 omega = rigid_->instrument_angular_velocity();
  instrument_->world_colliders(grip, rigid_->instrument_grip_velocity(), omega, moving_);
  reactions_[0] = BodyReaction{};
  reactions_[0].reference_point = rigid_->instrument_com_world();
  stepped_point_velocity_ = rigid_->instrument_com_velocity();
  stepped_angular_velocity_ = omega;
  // A particle step in flight stepped against the old shapes: it finishes, and hands on none
  // of their reaction.
  if (particle_step_pending_) {
    settle_particle_step();
    particle_reactions_[0] = reactions_[0];
    particle_point_velocity_ = stepped_point_velocity_;
    particle_angular_velocity_ = stepped_angular_velocity_;
  }
  if (nucleus_) nucleus_->forget_moving_wall_sums();
  emit(EventKind::kInstrumentExchange, instrument_index_, instrument_->config().name.c_str());
}

// The jaws follow the hand's grip no faster than a full closing in jaw_close_time_s (a button
// is all or nothing; the jaws are not), and Bullet's copies of them move with them. A silent
// device holds the jaws where they are.
void World::update_jaws(const DeviceSample& sample) {
  const double dt = config_.solver.dt_s;
  const double target =
      sample.stale || !std::isfinite(sample.grip) ? jaw_closure_ : std::clamp(sample.grip, 0.0, 1.0);
  const double step_max = dt / std::max(instrument_->config().jaw_close_time_s, dt);
  const double next = jaw_closure_ + std::clamp(target - jaw_closure_, -step_max, step_max);
  jaw_rate_ = (next - jaw_closure_) / dt;
  if (next == jaw_closure_) return;
  jaw_closure_ = next;
  for (int k = 0; k < InstrumentGeometry::kJawCount; ++k)
    rigid_->set_instrument_part(k, instrument_->jaw_pose(k, jaw_closure_));
}

// A grasp: each time the closing jaws reach jaw_hold_closure, every particle between them is
// taken out of the solve (those already held stay held) and carried with the instrument where
// it lies in the body frame; when the opening jaws reach jaw_release_closure, the held
// particles go free where they are, moving with the jaws (Nucleus::set_kinematic). Jaws opened
// less than that and closed again bite once more and keep what they held.
void World::grasp_or_release(const Pose& grip) {
  const InstrumentConfig& ic = instrument_->config();
  const bool closed = jaw_closure_ >= ic.jaw_hold_closure;
  const bool bite = closed && !jaws_were_closed_;
  jaws_were_closed_ = closed;
  if (bite) {
    const auto x = nucleus_->positions();
    for (std::size_t i = 0; i < x.size(); ++i) {
      const Vec3 local = grip.inverse_apply(x[i]);
      if (nucleus_->is_kinematic(i) || !instrument_->between_jaws(local, jaw_closure_)) continue;
      nucleus_->set_kinematic(i, true);
      held_.push_back(static_cast<std::int32_t>(i));
      held_local_.push_back(local);
    }
  } else if (!held_.empty() && jaw_closure_ <= ic.jaw_release_closure) {
    for (const std::int32_t i : held_) nucleus_->set_kinematic(static_cast<std::size_t>(i), false);
    held_.clear();
    held_local_.clear();
  }
}

// The held particles' velocities over the coming particle step: each goes to where its place
// in the body frame will be if the body moves on at its current velocities (the colliders'
// assumption too), so they stay on the body without drift. Their change of momentum is part
// of what they do to the instrument (add_held_reaction).
void World::carry_held(const Pose& grip, const Vec3& v_grip, const Vec3& omega) {
  const double dt = nucleus_dt_s();
  const auto x = nucleus_->positions();
  const auto v = nucleus_->velocities();
  const auto m = nucleus_->masses();
  held_momentum_change_ = Vec3::Zero();
  held_momentum_moment_ = Vec3::Zero();
  for (std::size_t k = 0; k < held_.size(); ++k) {
    const auto i = static_cast<std::size_t>(held_[k]);
    const Vec3 p = grip.apply(held_local_[k]);
    const Vec3 p_end = p + dt * (v_grip + omega.cross(p - grip.position));
    const Vec3 v_new = (p_end - x[i]) / dt;
    const Vec3 dp = m[i] * (v_new - v[i]);
    held_momentum_change_ += dp;
    held_momentum_moment_ += (x[i] - particle_reactions_[0].reference_point).cross(dp);
    nucleus_->set_fixed_velocity(i, v_new);
  }
}

// The hand shakes what lies on the open jaws off over the tray (InstrumentConfig::jaw_shake_off):
// while the jaws are open, or opening, and both plates' centres are outside the removal region,
// the gel slides on the plates. A 300 Pa s film clings to a still plate (it creeps off under its
// own weight at some 30 um/s), but a tap of the forceps on the tray's rim or a flick of the
// wrist gives the film accelerations many times g and throws it off; the model has no such
// shake, so it lets the film slide on the whole instrument instead (gel lodged between the jaws
// also touches the shaft's end at the hinge). From the first opening step, not only once the
// jaws have let go of the bite (jaw_release_closure): until then the bite is held rigidly where
// it lay between the jaws, and gel clinging to the parting plates was sheared between them and
// that rigid bite, which in module 03's 3000 Pa s gel pulled on the jaws with up to 10-20 N
// for ~30 ms, enough to overload the shaft by opening the jaws in the air. Inside the disc,
// and with the jaws closed or closing, it keeps its no-slip coupling.
void World::shake_off_jaws() {
  const InstrumentConfig& ic = instrument_->config();
  const bool opening = jaw_rate_ < 0.0;
  if (!ic.jaw_shake_off || (jaw_closure_ > ic.jaw_release_closure && !opening)) return;
  const Vec3 lo = config_.removal.min_m, hi = config_.removal.max_m;
  for (int k = 0; k < InstrumentGeometry::kJawCount; ++k)
    if (!outside_region(moving_[k].pose.position, lo, hi)) return;
  for (Collider& c : moving_) c.slip = true;  // the shake throws it off the shaft's end too
}

// What the held material does to the instrument over the particle step: its weight, the pull
// of its bonds to the free gel (until they tear) and the force that changed its momentum,
// added to the particles' reaction about the same reference point.
void World::add_held_reaction(double dt) {
  const auto x = nucleus_->positions();
  const auto m = nucleus_->masses();
  BodyReaction& r = particle_reactions_[0];
  Vec3 f_sum = -held_momentum_change_ / dt;
  Vec3 t_sum = -held_momentum_moment_ / dt;
  for (const std::int32_t id : held_) {
    const auto i = static_cast<std::size_t>(id);
    const Vec3 f = m[i] * config_.gravity_m_s2 + nucleus_->bond_pull_N(i);
    f_sum += f;
    t_sum += (x[i] - r.reference_point).cross(f);
  }
  r.force_N += f_sum;
  r.torque_Nm += t_sum;
}

// nucleus: the particles step against the instrument at its current pose and velocity, and
// gather what they do to it (force, torque, drag) about its centre of mass. Multi-rate: at
// every nucleus_every-th step only, over that many steps at once; the steps between hold the
// reaction (step_instrument) and spend no solver iterations. Pipelined: the particle step was
// launched at the end of the last due step (launch_particle_step) and is handed on here; the
// steps between keep pace with it.
void World::step_nucleus() {
  if (nucleus_ && !nucleus_due()) {
    // Between particle steps: their reaction is held, and the instrument's colliders stay those
    // they stepped against until the instrument's stage moves them.
    frame_.solver_iterations = 0;
    if (particle_step_pending_) pace_particle_step();
    return;
  }
  if (particle_step_pending_) {
    particle_run_before_s_ = particle_worker_->last_run_s();
    settle_particle_step();
    hand_on_particle_step();
    return;
  }
  // Pipelined, a particle step not launched ahead runs here: it takes over a grid
  // built ahead first, if one is pending.
  if (particle_worker_) nucleus_->adopt_rows_ahead();
  particle_colliders_ = {};
  particle_reaction_span_ = {};
  if (instrument_) {
    const Pose grip = rigid_->instrument_grip();
    const Vec3 com = rigid_->instrument_com_world();
    const Vec3 omega = rigid_->instrument_angular_velocity();
    const Vec3 v_com = rigid_->instrument_com_velocity();
    const Vec3 v_grip = v_com + omega.cross(grip.position - com);
    particle_reactions_[0] = BodyReaction{};
    particle_reactions_[0].reference_point = com;
    if (nucleus_ && instrument_->config().has_jaws()) {
      grasp_or_release(grip);
      carry_held(grip, v_grip, omega);
    }
    instrument_->world_colliders(grip, v_grip, omega, moving_, jaw_closure_, jaw_rate_);
    if (instrument_->config().has_jaws()) shake_off_jaws();
    particle_point_velocity_ = v_com;  // the reference point is the centre of mass here
    particle_angular_velocity_ = omega;
    particle_colliders_ = moving_;
    particle_reaction_span_ = particle_reactions_;
  }
  if (nucleus_) {
    particle_bone_due_ = particle_worker_ && bone_sample_among(steps_ + 1, steps_ + nucleus_every_);
    run_particle_step();
  }
  hand_on_particle_step();
}

void World::run_particle_step() {
  particle_report_ = NumericalReport{};
  nucleus_->step(nucleus_dt_s(), particle_colliders_, particle_reaction_span_, particle_report_);
  if (!held_.empty()) add_held_reaction(nucleus_dt_s());
  if (particle_bone_due_) gather_bone_cells(particle_bone_cells_, BoneLoadSample::kCapacity);
}

void World::hand_on_particle_step() {
  particle_step_pending_ = false;
  if (instrument_) {
    reactions_[0] = particle_reactions_[0];
    stepped_point_velocity_ = particle_point_velocity_;
    stepped_angular_velocity_ = particle_angular_velocity_;
  }
  if (!nucleus_) return;
  if (particle_worker_) {
    const auto x = nucleus_->positions();
    std::copy(x.begin(), x.end(), handed_on_x_.begin());
  }
  if (particle_bone_due_) bone_cells_ = particle_bone_cells_;
  frame_.solver_iterations = particle_report_.iterations;
  // The particles move only in their steps: the counts hold until the next is handed on.
  count_removed();
  frame_.broken_bonds = static_cast<std::int32_t>(nucleus_->broken_bond_count());
  frame_.active_particles = static_cast<std::int32_t>(nucleus_->active_count());
  if (!particle_report_.ok && !failed_) {
    emit(EventKind::kNumerical, particle_report_.residual, particle_report_.stage);
    failed_ = true;
  }
}

// Whether a bone sample falls at a step whose count (after it) is in [first, last].
bool World::bone_sample_among(std::int64_t first, std::int64_t last) const {
  if (bone_period_steps_ <= 0) return false;
  const std::int64_t next = (first + bone_period_steps_ - 1) / bone_period_steps_;
  return next * bone_period_steps_ <= last;
}

// After a due step: multi-rate, the step before the next particle step does its neighbour
// rebuild, when one is due, while nothing moves (the particles only move in their own steps),
// so the cost of a rebuild is spread over two steps. Not with jaws in hand: a grasp at the
// start of the particle step changes which particles are held before that step's rebuild
// would have been made. Pipelined: the next particle step is launched (and does its rebuild
// itself).
void World::prepare_nucleus() {
  if (!nucleus_) return;
  const bool jaws = instrument_ && instrument_->config().has_jaws();
  if (particle_worker_) {
    if ((steps_ - 1) % nucleus_every_ == 0 && !jaws) launch_particle_step();
    return;
  }
  if (nucleus_every_ < 2 || !nucleus_due() || jaws) return;
  nucleus_->prepare_next_step();
}

// Pipelined: the particle step of the next due step, launched now on the worker, against the
// instrument where it will be then if it moves on at its present velocities (k - 1 steps on:
// at 1 kHz and every 8th step, 7 ms, in which a hand's acceleration of 1 m/s^2 moves it 25 um
// off the straight line, against a lattice of 500 um). Its reaction is about that predicted
// centre of mass, its drag about the present velocities, which the due step's instrument
// update then corrects to the velocities reached (step_instrument), as within one step.
// Launched only while that prediction holds: the working point (turning included) covers at
// most a quarter of the lattice spacing before the due step. Faster (a flick, a collision),
// the due step runs its particle step itself, against the pose the instrument has then.
void World::launch_particle_step() {
  nucleus_->adopt_rows_ahead();
  particle_colliders_ = {};
  particle_reaction_span_ = {};
  if (instrument_) {
    const double lead_s = config_.solver.dt_s * static_cast<double>(nucleus_every_ - 1);
    const Pose grip = rigid_->instrument_grip();
    const Vec3 com = rigid_->instrument_com_world();
    const Vec3 omega = rigid_->instrument_angular_velocity();
    const Vec3 v_com = rigid_->instrument_com_velocity();
    const Vec3 v_tip = v_com + omega.cross(grip.apply(instrument_->working_point()) - com);
    if (v_tip.norm() * lead_s > 0.25 * config_.nucleus.spacing_m) return;
    const double turn_rad = omega.norm() * lead_s;
    const Quat turn = turn_rad > 0.0 ? Quat(Eigen::AngleAxisd(turn_rad, omega.normalized()))
                                     : Quat::Identity();
    const Vec3 com_then = com + lead_s * v_com;
    Pose grip_then;
    grip_then.position = com_then + turn * (grip.position - com);
    grip_then.orientation = (turn * grip.orientation).normalized();
    const Vec3 v_grip_then = v_com + omega.cross(grip_then.position - com_then);
    particle_reactions_[0] = BodyReaction{};
    particle_reactions_[0].reference_point = com_then;
    instrument_->world_colliders(grip_then, v_grip_then, omega, particle_moving_, jaw_closure_,
                                 jaw_rate_);
    particle_point_velocity_ = v_com;
    particle_angular_velocity_ = omega;
    particle_colliders_ = particle_moving_;
    particle_reaction_span_ = particle_reactions_;
  }
  const std::int64_t due = steps_ - 1 + nucleus_every_;  // the step it is handed on at
  particle_bone_due_ = bone_sample_among(due + 1, due + nucleus_every_);
  particle_step_pending_ = true;
  nucleus_->begin_rows_ahead();  // from the state the step starts from, before it runs
  particle_launched_at_ = std::chrono::steady_clock::now();
  particle_worker_->launch();
}

// Pipelined, between launch and hand-on: the j-th of the k - 1 steps after the launch does not
// end before j / (k - 1) of the time the particle step is expected to take has passed since
// its launch (or the step in flight has finished), so the wait for it is spread over the steps
// between and the due step finds it done. Expected: 10 % above the longer of the last two
// runs, as a run often takes a few tenths of a millisecond more than the one before (more
// particles awake); a step that finishes sooner ends the waits at once, so expecting too much
// costs nothing in the mean. When the steps are paced by a clock (a live attempt) the worker
// runs while they wait for their time, and none of them waits here. A neighbour rebuild begun
// at the launch (Nucleus::begin_rows_ahead) has its rows built here in equal shares.
void World::pace_particle_step() {
  const std::int64_t since = steps_ % nucleus_every_;  // 1 .. k-1
  const double part = static_cast<double>(since) / static_cast<double>(nucleus_every_ - 1);
  nucleus_->build_rows_ahead(part);
  const double expected_s =
      1.1 * std::max(particle_worker_->last_run_s(), particle_run_before_s_);
  particle_worker_->wait_until(particle_launched_at_ +
                               std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                   std::chrono::duration<double>(part * expected_s)));
}

// instrument: the implicit update under the coupling, the nucleus's reaction and gravity, which
// Bullet integrates with the contacts; then what the new state means: the coupling's force,
// the shaft's load, the danger zones, and whether the state is still finite. Without an
// instrument the rigid world holds only static solids: nothing in it moves.
void World::step_instrument(StepData& s) {
  if (!instrument_) return;
  const double dt = config_.solver.dt_s;
  BodyReaction reaction = reactions_[0];
  InstrumentBodyState body;
  body.mass_kg = instrument_->config().mass_kg;
  body.inertia_kg_m2 = rigid_->instrument_world_inertia();
  body.com_m = rigid_->instrument_com_world();
  body.com_velocity_m_s = rigid_->instrument_com_velocity();
  body.angular_velocity_rad_s = rigid_->instrument_angular_velocity();
  body.grip = rigid_->instrument_grip();
  if (!nucleus_due()) {
    // Held reaction: the particles' drag answers the instrument's velocity change since their
    // step (the implicit update then takes it on to the new velocity).
    const Vec3 v_point = body.com_velocity_m_s +
                         body.angular_velocity_rad_s.cross(reaction.reference_point - body.com_m);
    reaction.force_N -= reaction.drag_Ns_m * (v_point - stepped_point_velocity_);
    reaction.torque_Nm -=
        reaction.rot_drag_Nms * (body.angular_velocity_rad_s - stepped_angular_velocity_);
  }
  const InstrumentUpdate update =
      implicit_instrument_update(body, coupling_, s.target, reaction, config_.gravity_m_s2, dt);
  s.contact = rigid_->step(dt, update.force_N, update.torque_Nm);
  s.nucleus_force_N = reaction.force_N;

  const Pose grip = rigid_->instrument_grip();
  const Vec3 grip_velocity = rigid_->instrument_grip_velocity();
  s.coupling_force_N = coupling_force_N(coupling_, s.target, grip, grip_velocity);
  frame_.instrument = grip;
  frame_.tip_m = grip.apply(instrument_->working_point());

  // The particles' moment about the grip, taken where they pushed (the pose before the step).
  const Vec3 nucleus_moment =
      reaction.torque_Nm + (reaction.reference_point - body.grip.position).cross(reaction.force_N);
  check_shaft_load(grip, nucleus_moment, s.contact);

  // anatomy: danger zones against the instrument at its new pose; the force near a zone is what
  // the instrument presses on tissue (bone contact and nucleus).
  if (anatomy_) {
    instrument_->world_colliders(grip, grip_velocity, rigid_->instrument_angular_velocity(),
                                 moving_, jaw_closure_, jaw_rate_);
    evaluate_zones_and_emit(s.contact.force_N + s.nucleus_force_N);
  }

  if (!grip.position.allFinite() || !grip.orientation.coeffs().allFinite() ||
      !grip_velocity.allFinite()) {
    if (!failed_) emit(EventKind::kNumerical, 0.0, "instrument");
    failed_ = true;
  }
}

// The shaft's bending moment at the grip: the moment of the distal loads (particles, rigid
// contact, the instrument's weight) about the grip, less its torsion; events when it rises
// above the warning and the yield moment.
void World::check_shaft_load(const Pose& grip, const Vec3& nucleus_moment_Nm,
                             const RigidContact& contact) {
  const Vec3 weight_moment = (rigid_->instrument_com_world() - grip.position)
                                 .cross(instrument_->config().mass_kg * config_.gravity_m_s2);
  frame_.bending_moment_Nm = shaft_bending_moment_Nm(
      nucleus_moment_Nm + contact.torque_about_grip_Nm + weight_moment,
      grip.orientation * Vec3::UnitZ());
  const bool warn = frame_.bending_moment_Nm > summary_.warning_moment_Nm;
  const bool yield = frame_.bending_moment_Nm > summary_.yield_moment_Nm;
  if (warn && !warning_active_)
    emit(EventKind::kOverloadWarning, frame_.bending_moment_Nm, "shaft moment above warning");
  if (yield && !yield_active_)
    emit(EventKind::kOverloadYield, frame_.bending_moment_Nm, "shaft moment above yield");
  warning_active_ = warn;
  yield_active_ = yield;
}

// feedback: the user feels the coupling's reaction, limited for the device.
void World::send_feedback(StepData& s) {
  s.feedback = guard_.limit(-s.coupling_force_N, t_ + config_.solver.dt_s);
  if (s.feedback.clamped && !clamp_active_)
    emit(EventKind::kForceClamped, s.feedback.requested_N, "force above device maximum");
  clamp_active_ = s.feedback.clamped;
}

// record: the step's frame.
void World::record(const StepData& s) {
  t_ += config_.solver.dt_s;
  ++steps_;
  frame_.t_s = t_;
  frame_.device = s.input.target;
  frame_.input_valid = s.input.accepted;
  frame_.coupling_force_N = s.coupling_force_N;
  frame_.feedback_force_N = s.feedback.force_N;
  frame_.nucleus_force_N = s.nucleus_force_N;
  frame_.contact_force_N = s.contact.force_N;
  bone_sampled_ = bone_period_steps_ > 0 && steps_ % bone_period_steps_ == 0;
  if (bone_sampled_) sample_bone_loads();
}

// The loads on each vertebra at this step: the instrument's contact points with the bone
// meshes, and the particles' reaction on the bone grid gathered per cell of bone_load_cell_m
// (ParticleBoneCells): from the particles as they stand, or pipelined, as gathered beside the
// steps after the particle step last handed on. Reads state only.
void World::sample_bone_loads() {
  BoneLoadSample& out = bone_loads_;
  out.t_s = t_;
  out.count = 0;
  out.dropped = 0;
  if (instrument_) rigid_->gather_mesh_contacts(config_.solver.dt_s, out);
  if (!nucleus_) return;
  if (particle_worker_) {
    bone_cells_.append_to(out);
    return;
  }
  gather_bone_cells(bone_cells_, BoneLoadSample::kCapacity - out.count);
  bone_cells_.append_to(out);
}

void World::gather_bone_cells(ParticleBoneCells& cells, int capacity) const {
  cells.gather(nucleus_->static_forces(), nucleus_->positions(),
               anatomy_->vertebra_grid(VertebraLevel::kC4),
               anatomy_->vertebra_grid(VertebraLevel::kC5), config_.anatomy.bone_load_cell_m,
               capacity);
}

// Into the next free slot (none left: dropped until the next drain). The text fits the
// slot's reserve (see the constructor); one that did not would be cut, not allocated.
void World::emit(EventKind kind, double value, const char* detail) {
  if (pending_events_ >= events_.size()) return;
  Event& e = events_[pending_events_++];
  e.t_s = t_;
  e.kind = kind;
  e.value = value;
  e.zone = -1;
  e.detail.assign(detail, std::min(std::strlen(detail), e.detail.capacity()));
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
      const std::size_t before = pending_events_;
      emit(kind, value, z.name.c_str());
      if (pending_events_ > before) events_[before].zone = static_cast<std::int32_t>(i);
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
  out.insert(out.end(), events_.begin(),
             events_.begin() + static_cast<std::ptrdiff_t>(pending_events_));
  pending_events_ = 0;
}

std::span<const Vec3> World::particle_positions() const {
  if (!nucleus_) return {};
  return particle_worker_ ? std::span<const Vec3>(handed_on_x_) : nucleus_->positions();
}

std::span<const std::uint8_t> World::particle_materials() const {
  return nucleus_ ? nucleus_->materials() : std::span<const std::uint8_t>{};
}

bool World::removed_at(const Vec3& x) const {
  return outside_region(x, config_.removal.min_m, config_.removal.max_m);
}

bool World::is_removed(std::size_t i) const {
  settle_particle_step();
  return removed_at(nucleus_->positions()[i]);
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

std::uint64_t World::state_hash() const {
  settle_particle_step();
  std::uint64_t h = nucleus_ ? nucleus_->state_hash() : kFnvOffset;
  if (rigid_->has_instrument()) {
    const Pose g = rigid_->instrument_grip();
    h = fnv1a(g.position.data(), sizeof(double) * 3, h);
    h = fnv1a(g.orientation.coeffs().data(), sizeof(double) * 4, h);
  }
  return h;
}

}  // namespace acdr
