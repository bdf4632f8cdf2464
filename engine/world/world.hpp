// The simulated scene: built from a WorldConfig with only the parts it declares, stepped at a
// fixed rate by device samples, emitting a Frame per step and Events when they happen.
//
// The step is a fixed list of stages, each a member function and each timed: input (the
// guarded device pose becomes the coupling's target) -> nucleus (the particles against the
// instrument) -> instrument (its implicit update, Bullet's contacts, the shaft's load, the danger
// zones) -> feedback (the force the device renders) -> record (the frame).
//
// Multi-rate (SolverConfig::nucleus_every = k > 1): the particles step at every k-th step, over
// k dt at once, against the instrument's pose and velocity at that step; the instrument still
// steps every dt under the particles' reaction held from their step, its drag part moved to the
// instrument's velocity (the force less drag x the velocity gained since the particles' step),
// so the held reaction stays implicit in the drag as within one step.
//
// Pipelined (SolverConfig::nucleus_pipelined): at the end of each due step the next particle
// step is launched on a thread of its own (StepWorker), against the instrument where it will
// be at that step if it moves on at its present velocities, and it is handed on at that step
// as if it had run there: its reaction, the removed counts, its iterations and trouble. The
// steps between keep pace with it (each waits for at most its share of it), so no step waits
// the whole of it out. Whatever reads the particles between (nucleus(), is_removed(),
// state_hash(), an instrument exchange) first waits for the step in flight and sees the
// particles as it leaves them. With jaws in hand each particle step runs at its own step.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "engine/anatomy/anatomy.hpp"
#include "engine/core/bone_load.hpp"
#include "engine/core/frame.hpp"
#include "engine/core/step_worker.hpp"
#include "engine/devices/device_guard.hpp"
#include "engine/devices/input_device.hpp"
#include "engine/geometry/collider.hpp"
#include "engine/nucleus/nucleus.hpp"
#include "engine/rigid/instrument.hpp"
#include "engine/rigid/instrument_dynamics.hpp"
#include "engine/rigid/rigid_world.hpp"
#include "engine/world/particle_bone_cells.hpp"
#include "engine/world/world_config.hpp"

namespace acdr {

enum class StepStage : int { kInput = 0, kNucleus, kInstrument, kFeedback, kRecord, kCount };
const char* step_stage_name(StepStage stage);

/// Accumulated wall time per stage (s) and the number of steps measured.
struct StageTimes {
  std::array<double, static_cast<int>(StepStage::kCount)> seconds{};
  std::int64_t steps = 0;
};

/// Figures the assessment needs to interpret frames (stored with every recording).
struct WorldSummary {
  double dt_s = 0.0;
  double particle_volume_m3 = 0.0;
  std::int32_t initial_target = 0;     ///< particles of target material at start
  std::int32_t initial_protected = 0;  ///< particles of other materials at start
  double yield_moment_Nm = 0.0;
  double warning_moment_Nm = 0.0;
  double device_max_force_N = 0.0;
  // anatomy: the danger zones, in the order of Frame::zones
  struct Zone {
    std::string name;
    double warning_distance_m = 0.0;
    double force_limit_N = 0.0;
    bool never_event = false;
  };
  std::vector<Zone> zones;
};

/// Events a world holds between two drain_events() calls; later ones are dropped.
inline constexpr std::size_t kMaxPendingEvents = 4096;

class World {
 public:
  explicit World(const WorldConfig& config);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// Advances one fixed step following the device sample; returns the frame it produced.
  const Frame& step(const DeviceSample& sample);

  double time_s() const { return t_; }
  std::int64_t step_count() const { return steps_; }
  /// True once numerical trouble was detected (a kNumerical event was emitted).
  bool failed() const { return failed_; }

  /// Moves the events emitted since the last call to `out` (appends).
  void drain_events(std::vector<Event>& out);

  const WorldConfig& config() const { return config_; }
  const WorldSummary& summary() const { return summary_; }
  const Frame& last_frame() const { return frame_; }
  const StageTimes& stage_times() const { return times_; }
  /// The particles, once a pipelined particle step in flight has finished.
  const Nucleus* nucleus() const {
    settle_particle_step();
    return nucleus_.get();
  }
  /// The particles' positions as the last particle step handed on left them, m (empty without
  /// a nucleus). Pipelined, a copy taken at the hand-on, so a reader between steps (the trainee
  /// view) does not wait for the particle step in flight; otherwise the particles' own.
  std::span<const Vec3> particle_positions() const;
  /// Each particle's material (an index into the configured materials; fixed at the build).
  std::span<const std::uint8_t> particle_materials() const;
  /// Whether a particle at x counts as removed: outside the removal region.
  bool removed_at(const Vec3& x) const;
  /// The anatomical scene (vertebrae, grids, zones), or null without anatomy.
  const Anatomy* anatomy() const { return anatomy_.get(); }
  /// The instrument in hand, or null without one.
  const InstrumentGeometry* instrument() const { return instrument_; }
  /// Its index among WorldConfig::instruments (0 when the scene has one instrument).
  int instrument_index() const { return instrument_index_; }
  const std::vector<Collider>& static_colliders() const { return static_colliders_; }
  /// Instrument colliders at the current pose (empty without an instrument).
  const std::vector<Collider>& instrument_colliders() const { return moving_; }
  /// The instrument's jaw closure, 0 open .. 1 closed (0 without jaws).
  double jaw_closure() const { return jaw_closure_; }
  /// The particles the jaws hold now (empty unless a rongeur's jaws are closed on some).
  std::span<const std::int32_t> held_particles() const { return held_; }
  /// Particle i has left the removal region.
  bool is_removed(std::size_t i) const;
  /// FNV-1a over the nucleus and instrument state, for determinism checks.
  std::uint64_t state_hash() const;
  /// The loads on the bone when the last step sampled them (AnatomyConfig::bone_load_period_s,
  /// at the steps that reach each multiple of it), else null. Valid until the next step.
  const BoneLoadSample* bone_loads() const { return bone_sampled_ ? &bone_loads_ : nullptr; }

 private:
  struct StepData;  // what one step's stages hand on to the next
  // The stages of step(), in order.
  void read_input(const DeviceSample& sample, StepData& s);
  void step_nucleus();
  /// Whether this step steps the particles (every nucleus_every-th step, the first included).
  bool nucleus_due() const { return steps_ % nucleus_every_ == 0; }
  /// The particles' step: nucleus_every World steps.
  double nucleus_dt_s() const { return config_.solver.dt_s * static_cast<double>(nucleus_every_); }
  void prepare_nucleus();
  /// The particle step against particle_moving_, into particle_reactions_ and particle_report_
  /// (what the StepWorker runs when pipelined).
  void run_particle_step();
  /// Hands the finished particle step's results on to the instrument and the frame.
  void hand_on_particle_step();
  void launch_particle_step();
  void pace_particle_step();
  bool bone_sample_among(std::int64_t first, std::int64_t last) const;
  /// Waits for a pipelined particle step in flight (at once when none is).
  void settle_particle_step() const {
    if (particle_worker_) particle_worker_->wait();
  }
  void step_instrument(StepData& s);
  void send_feedback(StepData& s);
  void record(const StepData& s);

  void update_jaws(const DeviceSample& sample);
  void exchange_instrument_when_out();
  bool instrument_outside_region() const;
  void grasp_or_release(const Pose& grip);
  void carry_held(const Pose& grip, const Vec3& v_grip, const Vec3& omega);
  void add_held_reaction(double dt);
  void shake_off_jaws();
  void check_shaft_load(const Pose& grip, const Vec3& nucleus_moment_Nm,
                        const RigidContact& contact);
  void evaluate_zones_and_emit(const Vec3& tissue_force_N);
  void count_removed();
  void sample_bone_loads();
  void gather_bone_cells(ParticleBoneCells& cells, int capacity) const;
  void emit(EventKind kind, double value, const char* detail);

  WorldConfig config_;
  WorldSummary summary_;
  // Declared before the rigid world and the nucleus: their colliders point into its grids.
  std::unique_ptr<Anatomy> anatomy_;
  std::vector<InstrumentGeometry> tray_;  // WorldConfig::instruments (or the one instrument)
  const InstrumentGeometry* instrument_ = nullptr;  // the one in hand, in tray_
  int instrument_index_ = 0;
  int requested_instrument_ = 0;  // what the hand last asked for (DeviceSample::instrument)
  std::vector<Collider> static_colliders_;
  std::unique_ptr<RigidWorld> rigid_;
  std::unique_ptr<Nucleus> nucleus_;
  DeviceGuard guard_;
  CouplingGains coupling_;  // the coupling's gains, critical damping resolved

  std::vector<Collider> moving_;        // instrument colliders, world frame (capacity fixed)
  std::vector<BodyReaction> reactions_; // one per moving body, as the instrument holds them
  // Event slots (kMaxPendingEvents), [0, pending_events_) pending; each slot's text keeps
  // room for the longest text the world can emit, so emitting allocates nothing.
  std::vector<Event> events_;
  std::size_t pending_events_ = 0;
  Frame frame_;
  StageTimes times_;
  double t_ = 0.0;
  std::int64_t steps_ = 0;
  std::int64_t nucleus_every_ = 1;  // SolverConfig::nucleus_every, at least 1
  // The instrument's velocities when the particles last stepped (their reaction's drag is
  // about them): of the reaction's reference point, and angular.
  Vec3 stepped_point_velocity_ = Vec3::Zero();
  Vec3 stepped_angular_velocity_ = Vec3::Zero();
  // Rongeur jaws: the closure (0 open .. 1 closed), its rate this step (1/s), and what they
  // hold: particle indices and their places in the body frame (capacity N, fixed at build).
  double jaw_closure_ = 0.0;
  double jaw_rate_ = 0.0;
  bool jaws_were_closed_ = false;  // at or above jaw_hold_closure at the last particle step
  std::vector<std::int32_t> held_;
  std::vector<Vec3> held_local_;
  Vec3 held_momentum_change_ = Vec3::Zero();  // over the particle step, kg m/s
  Vec3 held_momentum_moment_ = Vec3::Zero();  // its moment about the reaction's reference point
  bool failed_ = false;
  bool input_rejecting_ = false;
  bool input_lost_ = false;
  bool warning_active_ = false;
  bool yield_active_ = false;
  bool clamp_active_ = false;
  // Per-zone state of the last step, for edge-triggered zone events.
  std::array<ZoneSample, kMaxZones> zone_samples_{};
  std::array<std::uint8_t, kMaxZones> zone_warn_active_{};
  std::array<std::uint8_t, kMaxZones> zone_inside_active_{};
  std::array<std::uint8_t, kMaxZones> zone_force_active_{};
  Quat last_target_orientation_ = Quat::Identity();
  // Bone loads (AnatomyConfig::bone_load_period_s): the sample, its period in steps, and the
  // particles' part (pipelined: as handed on with the last particle step).
  BoneLoadSample bone_loads_;
  bool bone_sampled_ = false;
  std::int64_t bone_period_steps_ = 0;
  ParticleBoneCells bone_cells_;
  // The particle step's own inputs and outputs: the colliders it steps against (a copy when
  // pipelined; capacity fixed), the reactions it gathers, its report, the instrument's
  // velocities at its launch, and whether one was launched and not yet handed on.
  std::vector<Collider> particle_moving_;
  std::vector<BodyReaction> particle_reactions_;
  std::span<const Collider> particle_colliders_;
  std::span<BodyReaction> particle_reaction_span_;
  NumericalReport particle_report_;
  Vec3 particle_point_velocity_ = Vec3::Zero();
  Vec3 particle_angular_velocity_ = Vec3::Zero();
  bool particle_step_pending_ = false;
  double particle_run_before_s_ = 0.0;  // the run before the last (pace_particle_step)
  std::vector<Vec3> handed_on_x_;  // pipelined: the positions at the last hand-on
  std::chrono::steady_clock::time_point particle_launched_at_{};
  // Pipelined with bone loads: the particle step in flight gathers its reaction on the bone
  // (when a sample will read it) into particle_bone_cells_.
  bool particle_bone_due_ = false;
  ParticleBoneCells particle_bone_cells_;
  // Pipelined particle steps' worker (null otherwise); last, so it is ended first.
  std::unique_ptr<StepWorker> particle_worker_;
};

}  // namespace acdr
