// Numerical stability stress suite (`acdr stress`): the box module's scene driven
// through the whole World (device guard, virtual coupling, instrument, nucleus) by a scripted
// device, swept over time step (and multi-rate particle steps), bond stiffness, viscosity, instrument speed, a 5 cm teleport and
// NaN/Inf device samples. Each case reports NaN, peak particle speed, kinetic-energy growth
// while nothing is driven, particles that crossed a wall (or entered a solid), and the peak
// force sent to the device against its limit.
#pragma once

#include <string>
#include <vector>

namespace acdr {

struct StressCaseSpec {
  std::string name;
  double dt_s = 1.0e-3;
  int nucleus_every = 1;         ///< the particles step every this many steps (multi-rate)
  bool pipelined = false;        ///< each particle step launched a step ahead (SolverConfig)
  double bond_stiffness_N_m = 5.0;
  double viscosity_Pa_s = 250.0;
  double speed_m_s = 0.05;       ///< commanded instrument speed during the scoop
  bool teleport = false;         ///< device pose jumps 5 cm for 0.1 s mid-scoop
  bool bad_input = false;        ///< NaN and Inf device samples mid-scoop
  double spacing_m = 1.0e-3;     ///< particle spacing of the block
  double hold_s = 0.3;           ///< still device after the scoop (energy window: second half)
};

struct StressResult {
  std::string name;
  bool passed = false;
  bool nan = false;                    ///< a NaN/Inf or a numerical event occurred
  std::string nan_stage;
  double max_particle_speed_m_s = 0.0;
  double hold_energy_start_J = 0.0;    ///< kinetic energy at the start of the hold's 2nd half
  double hold_energy_end_J = 0.0;      ///< and at its end
  /// Change of the nucleus' mechanical energy (kinetic + gravity + springs + pressure) over the
  /// hold's second half, J (reported; see energy_grew for the pass rule).
  double hold_energy_change_J = 0.0;
  /// Mean kinetic energy over the first and the second half of the hold's second half, J.
  double hold_kinetic_early_J = 0.0;
  double hold_kinetic_late_J = 0.0;
  /// Mean mechanical energy of the hold's last quarter minus that of the quarter before, J.
  double hold_energy_trend_J = 0.0;
  /// Standard deviation of the per-step mechanical energy over the quarter before the last, J:
  /// how much the energy jitters without a trend (jammed particles' pressure energy).
  double hold_energy_jitter_J = 0.0;
  /// Energy grew with nothing driven (hold_energy_grew).
  bool energy_grew = false;
  int tunnelled = 0;                   ///< particles whose path crossed a wall (pass: 0)
  /// Particles found deeper than h/4 inside the instrument after a step (not a failure: the
  /// instrument moves after the particles in a World step, and the overlap is pushed out on the
  /// side the particle came from in the next step; reported to watch it).
  int into_instrument = 0;
  double peak_device_force_N = 0.0;
  double device_limit_N = 0.0;
  int steps = 0;
  int particles = 0;
  int rejected_samples = 0;            ///< device samples the guard rejected
  double ms_per_step = 0.0;            ///< wall time
};

/// The built-in sweep. `fast`: 2 mm spacing and shorter holds (ctest).
std::vector<StressCaseSpec> builtin_stress_cases(bool fast = false);

/// The pass rule for energy with nothing driven: the trend (last quarter's mean minus the
/// quarter before's) exceeds 1 % of the kinetic energy plus twice the jitter of the quarter
/// before, + 1e-12 J. A growth, steady or exponential, moves the mean by more than the spread
/// it had a quarter earlier (a steady ramp: trend = sqrt(12) = 3.5 spreads); bounded jitter
/// moves the quarter means by a fraction of it.
bool hold_energy_grew(double trend_J, double kinetic_early_J, double jitter_early_J);

/// Runs one case to completion (never throws on numerical trouble: it is the result).
StressResult run_stress_case(const StressCaseSpec& spec);

}  // namespace acdr
