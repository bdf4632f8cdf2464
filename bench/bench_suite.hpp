// `acdr bench` as a library: the work-precision grid (our solver and the Bullet soft-body
// peer against a converged reference), cost against particle count with a fitted exponent,
// and the skips switched on and off with the error each costs. Plain data out; the command line
// (cli/bench_command) formats tables, CSV, JSON (bench_report_format.hpp) and the plot
// (work_precision_plot.hpp).
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "bench/bone_solve_bench.hpp"
#include "bench/bullet_peer.hpp"
#include "bench/scene_run.hpp"

namespace acdr {

/// A scene to benchmark: a scenario file and the trajectory that plays it.
struct BenchScene {
  std::string name;          ///< "box", "c4c5", ...
  std::string scenario_path;
  std::string trajectory_path;
  /// Trajectory time the work-precision window starts at (s): just before the instrument
  /// enters the material, so the window holds the costly, force-carrying part of a scoop.
  double window_start_s = 0.0;
  /// > 0: replaces the scenario's particle spacing (m), e.g. a tiny scene for a test.
  double spacing_m = 0.0;
  /// false: the grid's finer and coarser lattices are not run on this scene (a scene whose
  /// lattice is the target itself: at x0.5 it would be eight times the particles).
  bool spacing_sweep = true;
  /// Also a point at the scene's own settings with its particle steps pipelined (the other way
  /// round when the scene pipelines them): the same step, its cost and error side by side.
  bool pipelined_point = false;
  /// Trajectory time every work-precision run (the reference's and each point's) starts at,
  /// before its window: a time when the instrument is still outside the material, so that the
  /// window starts from the state the run reached by itself, as in an attempt, not from a
  /// fresh lattice with the instrument placed inside it. The lead (window_start_s - this,
  /// rounded up to whole sample windows) is neither timed nor compared. < 0: from the
  /// trajectory's start.
  double run_from_s = -1.0;
};

/// What the benchmark runs: the grid of the work-precision diagram, the peer's sweep, the
/// scaling lattices and the skip runs. `default_grid` gives the full and the quick grids.
struct BenchGrid {
  double window_s = 1.5;             ///< simulated time of each work-precision run
  double sample_s = 0.012;           ///< force windows compared between runs (RunWindow)
  double reference_dt_s = 0.5e-3;    ///< the converged reference: finest step ...
  double reference_tolerance = 1e-7; ///< ... tightest PCG tolerance
  int reference_max_iterations = 2000;
  std::vector<double> dts_s{0.5e-3, 1e-3, 2e-3};
  std::vector<double> tolerances{1e-1, 1e-2, 1e-3, 1e-4, 1e-5};
  /// Finer and coarser lattices, as multiples of the scene's spacing (at its own dt and
  /// tolerance), compared with the reference at the scene's spacing.
  std::vector<double> spacing_factors{0.5, 0.75, 1.5};
  std::vector<int> peer_iterations{1, 2, 4, 8, 16};  ///< Bullet position iterations swept
  /// The peer on scenes with anatomy: the bone is two static triangle meshes there, which
  /// Bullet's soft body meets triangle by triangle (100-300x slower than real time at 900
  /// nodes), so the full grid sweeps fewer iterations there and the quick grid leaves it out.
  bool peer_on_anatomy = true;
  std::vector<int> anatomy_peer_iterations{2, 8};
  /// Scaling: particle spacings on the first scene (every particle awake), steps per point.
  std::vector<double> scaling_spacings_m{1.7e-3, 1.25e-3, 1.0e-3, 0.8e-3, 0.62e-3, 0.45e-3};
  int scaling_warmup_steps = 5;
  int scaling_timed_steps = 30;
  /// Skips, on the first scene: runs start this long before the work-precision window (the
  /// particles need time at rest to fall asleep) and last `skip_window_s`.
  double skip_lead_s = 0.8;
  double skip_window_s = 2.5;
  /// Each of our solver's work-precision runs is timed this many times and the fastest kept:
  /// the work is identical (deterministic: the traces are compared), so the spread is the
  /// host's. On a shared machine runs minutes apart differ by up to ~1.5x.
  int timing_runs = 3;
};

/// The full grid, or the quick one (about three minutes on a 2-core machine).
BenchGrid default_grid(bool quick);

struct BenchConfig {
  bool quick = false;  ///< informational (the grid decides what runs)
  BenchGrid grid;
  std::vector<BenchScene> scenes;
  /// Progress: what runs now and the fraction of the whole benchmark done (0..1).
  std::function<void(const std::string& what, double fraction)> progress;
  /// Draws a frame of the world (the "renderer" skip: on = headless, off = this is called at
  /// ~60 Hz). Empty: that skip is not measured.
  std::function<void(const World&)> render_frame;
};

/// One point of the work-precision diagram.
struct WorkPoint {
  std::string scene;
  std::string solver;      ///< "acdr" or "bullet"
  std::string settings;    ///< e.g. "dt=1ms tol=1e-4 h=1mm"
  double dt_s = 0.0;
  double tolerance = 0.0;  ///< acdr: PCG tolerance
  double spacing_m = 0.0;
  int iterations = 0;      ///< bullet: position iterations
  double link_stiffness = 0.0;  ///< bullet: kLST
  std::size_t particles = 0;
  std::size_t links = 0;
  double wall_s_per_sim_s = 0.0;
  double cpu_s_per_sim_s = 0.0;
  int timing_runs = 1;                    ///< timed runs; the times above are the fastest
  double slowest_wall_s_per_sim_s = 0.0;  ///< the slowest of those runs (host noise)
  double mean_step_ms = 0.0;              ///< wall time per step of the fastest run, ms
  double p99_step_ms = 0.0;               ///< its 99th-percentile step, wall, ms
  /// CPU time per step per particle of the scene (every particle, awake or not), us.
  double cpu_us_per_particle_step = 0.0;
  double force_rms_error = 0.0;
  double force_peak_error = 0.0;
  double removed_error = 0.0;
  double mean_iterations = 0.0;
  double mean_active = 0.0;
  bool is_default = false;    ///< the scene's own settings
  bool is_reference = false;  ///< the converged run the others are measured against
  bool failed = false;
};

struct ScalingPoint {
  double spacing_m = 0.0;
  std::size_t particles = 0;
  double wall_ms_per_step = 0.0;
  double cpu_ms_per_step = 0.0;
  double mean_iterations = 0.0;
  double cpu_us_per_iteration_per_particle = 0.0;
  double cpu_us_per_particle_step = 0.0;  ///< CPU time per step per particle, us
  double p99_step_ms = 0.0;               ///< 99th-percentile step, wall, ms
  int timing_runs = 1;                    ///< timed runs; the times above are the fastest
};

/// Least-squares fit cost = c * N^exponent on log-log axes.
struct PowerFit {
  double exponent = 0.0;
  double coefficient = 0.0;
  double r2 = 0.0;
};

struct SkipResult {
  std::string name;         ///< "sleep", "contact_culling", "undeclared_parts", "headless"
  std::string description;
  double on_wall_s_per_sim_s = 0.0;   ///< skip on (the default)
  double off_wall_s_per_sim_s = 0.0;  ///< skip off
  double on_cpu_s_per_sim_s = 0.0;
  double off_cpu_s_per_sim_s = 0.0;
  double gain = 0.0;                  ///< off / on (CPU time)
  double force_rms_error = 0.0;       ///< on against off
  double removed_error = 0.0;
  bool measured = false;
};

struct BenchReport {
  std::vector<WorkPoint> points;
  std::vector<ScalingPoint> scaling;
  PowerFit scaling_fit;            ///< CPU ms per step against particles (all awake)
  PowerFit per_iteration_fit;      ///< CPU ms per PCG iteration against particles
  std::string scaling_scene;
  std::vector<SkipResult> skips;
  std::string skips_scene;
  std::string machine;             ///< CPU model, cores, SIMD path, load average at start and end
  double wall_s = 0.0;             ///< the whole benchmark
  bool quick = false;
  /// The bone's solves per load update, for each scene that models the bone (its
  /// work-precision window's load samples, solved as an attempt's worker solves them).
  std::vector<BoneSolveFigures> bone;
  /// The trajectory window of each scene's work-precision runs (same order as the scenes).
  std::vector<std::pair<std::string, RunWindow>> windows;
};

/// Runs the benchmark. Returns false with `error` set when a scene cannot be loaded.
bool run_bench_suite(const BenchConfig& config, BenchReport* report, std::string* error);

/// Fits cost = c * n^e by least squares on (log n, log cost).
PowerFit fit_power(const std::vector<double>& n, const std::vector<double>& cost);

/// One line describing the machine: CPU model, logical CPUs, the SIMD path this program was
/// compiled for (cmake/simd.cmake), load average.
std::string describe_machine();

}  // namespace acdr
