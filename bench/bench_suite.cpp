// The benchmark suite: work-precision grid, Bullet peer, scaling, skips.
#include "bench/bench_suite.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>

#include "bench/bone_solve_bench.hpp"
#include "bench/run_loop.hpp"
#include "engine/anatomy/anatomy.hpp"
#include "bench/trace_error.hpp"
#include "engine/rigid/instrument.hpp"
#include "engine/nucleus/nucleus.hpp"
#include "engine/rigid/rigid_world.hpp"
#include "scenarios/scenario_loader.hpp"

namespace acdr {
namespace {

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string acdr_settings_text(double dt, double tol, double h) {
  return "dt=" + fmt("%g", dt * 1e3) + "ms tol=" + fmt("%g", tol) + " h=" + fmt("%g", h * 1e3) +
         "mm";
}

/// The multi-rate setting for a point's label: empty when the particles step at every step,
/// unpipelined.
std::string nucleus_every_text(const SolverConfig& solver) {
  return (solver.nucleus_every > 1 ? " nucleus every " + std::to_string(solver.nucleus_every)
                                   : std::string()) +
         (solver.nucleus_pipelined ? " pipelined" : "");
}

/// Parts of a C4-C5 scene that the box module does not declare (two vertebral bodies, the
/// posterior elements as capsules, the uncinate processes), placed beside the box: what an
/// engine that always built every part would carry along. They touch no particle.
std::vector<Collider> undeclared_parts() {
  std::vector<Collider> out;
  auto box = [&](const Vec3& c, const Vec3& he) {
    Collider k;
    k.kind = ColliderKind::kBox;
    k.pose.position = c;
    k.half_extents_m = he;
    out.push_back(k);
  };
  auto capsule = [&](const Vec3& c, double half, double r, const Vec3& axis) {
    Collider k;
    k.kind = ColliderKind::kCapsule;
    k.pose.position = c;
    k.pose.orientation = Quat::FromTwoVectors(Vec3::UnitZ(), axis);
    k.half_length_m = half;
    k.radius_m = r;
    out.push_back(k);
  };
  const Vec3 o(0.08, 0.0, 0.01);  // 80 mm beside the box
  box(o + Vec3(0, 0, 0.012), Vec3(0.009, 0.0075, 0.006));    // C4 body
  box(o + Vec3(0, 0, -0.004), Vec3(0.009, 0.0075, 0.006));   // C5 body
  capsule(o + Vec3(-0.012, 0.008, 0.012), 0.006, 0.003, Vec3(1, 0.3, 0).normalized());   // pedicles
  capsule(o + Vec3(-0.012, -0.008, 0.012), 0.006, 0.003, Vec3(1, -0.3, 0).normalized());
  capsule(o + Vec3(-0.02, 0.006, 0.012), 0.008, 0.002, Vec3(0.3, 1, 0).normalized());    // laminae
  capsule(o + Vec3(-0.02, -0.006, 0.012), 0.008, 0.002, Vec3(0.3, -1, 0).normalized());
  capsule(o + Vec3(-0.03, 0, 0.012), 0.008, 0.0025, Vec3(1, 0, -0.3).normalized());      // spinous
  capsule(o + Vec3(0.002, 0.008, 0.006), 0.002, 0.0015, Vec3(0, 0, 1));                  // uncinate
  capsule(o + Vec3(0.002, -0.008, 0.006), 0.002, 0.0015, Vec3(0, 0, 1));
  return out;
}

/// The nucleus alone (no rigid world): the instrument's colliders follow a recorded path,
/// `extra` statics join the scene's own. Gives the force on the instrument per window.
RunTrace run_nucleus_only(const WorldConfig& config, const Pose& start,
                          const std::vector<Pose>& path, const RunWindow& window,
                          const std::vector<Collider>& extra) {
  RunTrace out;
  std::vector<Collider> statics = build_static_colliders(config.ground, config.box);
  statics.insert(statics.end(), extra.begin(), extra.end());
  Nucleus nucleus(config.nucleus, config.solver, config.gravity_m_s2, statics);
  const InstrumentGeometry geometry(config.instrument);
  std::vector<Collider> moving;
  moving.reserve(geometry.local_colliders().size());
  std::vector<BodyReaction> reactions(1);
  const double dt = config.solver.dt_s;
  const double duration = window.duration_s > 0.0 ? window.duration_s
                                                  : window.sample_s * double(path.size());
  out.particles = nucleus.particle_count();
  out.bonds = nucleus.bond_count();
  const std::int64_t steps = run_timed_loop(duration, dt, window, out, [&](std::int64_t k) {
    const PathMotion m = motion_on_path(start, path, window.sample_s, double(k) * dt, dt);
    geometry.world_colliders(m.pose, m.velocity_m_s, m.angular_velocity_rad_s, moving);
    reactions[0] = BodyReaction{};
    reactions[0].reference_point = m.pose.position;
    NumericalReport report;
    nucleus.step(dt, moving, reactions, report);
    out.mean_iterations += report.iterations;
    out.mean_active += static_cast<double>(nucleus.active_count());
    if (!report.ok) out.failed = true;  // noted; the run goes on
    return LoopStep{reactions[0].force_N, std::nullopt, false};
  });
  out.steps = steps;
  out.sim_s = double(steps) * dt;
  if (steps > 0) {
    out.mean_iterations /= double(steps);
    out.mean_active /= double(steps);
  }
  out.state_hash = nucleus.state_hash();
  return out;
}

// The same run `runs` times (run(r) is the r-th): the first one's trace with the fastest run's
// wall time and step times, and the least CPU time of any, since the host's speed only ever
// adds time; *slowest_wall_s the slowest run's wall time. A repeat whose forces differ is not
// deterministic, a bug: the trace is marked failed.
RunTrace fastest_of(int runs, const std::function<RunTrace(int)>& run, double* slowest_wall_s) {
  RunTrace first = run(0);
  double slowest = first.wall_s;
  for (int r = 1; r < runs && !first.failed; ++r) {
    const RunTrace again = run(r);
    if (again.force_N != first.force_N) {
      first.failed = true;
      break;
    }
    slowest = std::max(slowest, again.wall_s);
    if (again.wall_s < first.wall_s) {
      first.wall_s = again.wall_s;
      first.p99_step_wall_s = again.p99_step_wall_s;
      first.max_step_wall_s = again.max_step_wall_s;
    }
    first.cpu_s = std::min(first.cpu_s, again.cpu_s);
  }
  if (slowest_wall_s != nullptr) *slowest_wall_s = slowest;
  return first;
}

WorkPoint make_point(const std::string& scene, const RunTrace& run, const RunTrace& reference) {
  WorkPoint p;
  p.scene = scene;
  const TraceError e = trace_error(run, reference);
  p.particles = run.particles;
  p.links = run.bonds;
  p.wall_s_per_sim_s = run.sim_s > 0.0 ? run.wall_s / run.sim_s : 0.0;
  p.cpu_s_per_sim_s = run.sim_s > 0.0 ? run.cpu_s / run.sim_s : 0.0;
  p.force_rms_error = e.force_rms;
  p.force_peak_error = e.force_peak;
  p.removed_error = e.removed;
  p.mean_iterations = run.mean_iterations;
  p.mean_active = run.mean_active;
  p.failed = run.failed;
  const double timed = static_cast<double>(std::max<std::int64_t>(1, run.timed_steps));
  p.mean_step_ms = 1e3 * run.wall_s / timed;
  p.p99_step_ms = 1e3 * run.p99_step_wall_s;
  p.cpu_us_per_particle_step =
      run.particles > 0 ? 1e6 * run.cpu_s / timed / static_cast<double>(run.particles) : 0.0;
  return p;
}

}  // namespace

PowerFit fit_power(const std::vector<double>& n, const std::vector<double>& cost) {
  PowerFit fit;
  const std::size_t m = std::min(n.size(), cost.size());
  if (m < 2) return fit;
  double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
  for (std::size_t k = 0; k < m; ++k) {
    const double x = std::log(n[k]), y = std::log(cost[k]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    syy += y * y;
  }
  const double d = m * sxx - sx * sx;
  if (d <= 0.0) return fit;
  fit.exponent = (m * sxy - sx * sy) / d;
  const double b = (sy - fit.exponent * sx) / m;
  fit.coefficient = std::exp(b);
  const double ss_tot = syy - sy * sy / m;
  double ss_res = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    const double r = std::log(cost[k]) - (b + fit.exponent * std::log(n[k]));
    ss_res += r * r;
  }
  fit.r2 = ss_tot > 0.0 ? 1.0 - ss_res / ss_tot : 1.0;
  return fit;
}

std::string describe_machine() {
  std::string model = "unknown CPU";
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  int cpus = 0;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0) {
      ++cpus;
      const auto colon = line.find(':');
      if (colon != std::string::npos) model = line.substr(colon + 2);
    }
  }
  std::string load;
  std::ifstream loadavg("/proc/loadavg");
  std::getline(loadavg, load);
  std::ostringstream out;
  out << model << ", " << cpus << " logical CPUs, SIMD path " << ACDR_SIMD_PATH
      << ", load average " << load.substr(0, 14);
  return out.str();
}

BenchGrid default_grid(bool quick) {
  BenchGrid g;
  if (!quick) return g;
  // Quick: 0.3 s windows of the scoops, two steps, two tolerances, one coarser lattice, two
  // peer sweeps (box only), four lattices for the scaling with few steps, short skip runs.
  g.window_s = 0.3;
  g.reference_tolerance = 1e-5;
  g.dts_s = {1e-3, 2e-3};
  g.tolerances = {1e-2, 1e-4};
  g.spacing_factors = {1.5};
  g.peer_iterations = {2, 8};
  g.peer_on_anatomy = false;
  g.scaling_spacings_m = {1.7e-3, 1.0e-3, 0.62e-3, 0.45e-3};  // 1k, 5k, 20k, 52k particles
  g.scaling_warmup_steps = 2;
  g.scaling_timed_steps = 4;
  g.skip_lead_s = 0.3;
  g.skip_window_s = 0.7;
  return g;
}

namespace {

/// One unit of work with its share of the progress bar (~ steps x particles, relative).
struct Job {
  std::string what;
  double weight = 1.0;
  std::function<void(const std::function<void(double)>&)> run;
};

}  // namespace

bool run_bench_suite(const BenchConfig& config, BenchReport* report, std::string* error) {
  const auto t_start = std::chrono::steady_clock::now();
  BenchReport& rep = *report;
  rep = BenchReport{};
  rep.machine = describe_machine();
  rep.quick = config.quick;
  const BenchGrid& grid = config.grid;

  struct Loaded {
    BenchScene scene;
    WorldConfig world;
    Trajectory trajectory;
    RunWindow window;
    RunTrace reference;
    BoneModelConfig bone;
  };
  std::vector<Loaded> scenes;
  scenes.reserve(config.scenes.size());
  for (const BenchScene& s : config.scenes) {
    const LoadResult loaded = load_scenario_file(s.scenario_path);
    if (!loaded.ok()) {
      *error = s.scenario_path + ": cannot load the scenario";
      if (!loaded.errors.empty()) *error = loaded.errors.front().to_string();
      return false;
    }
    auto trajectory = Trajectory::load_csv(s.trajectory_path, error);
    if (!trajectory) return false;
    Loaded l{s, loaded.model->world, std::move(*trajectory), {}, {}, loaded.model->bone};
    if (s.spacing_m > 0.0) l.world.nucleus.spacing_m = s.spacing_m;
    l.window.start_s = s.window_start_s;
    l.window.duration_s = grid.window_s;
    l.window.sample_s = grid.sample_s;
    const double from_s = s.run_from_s < 0.0 ? 0.0 : s.run_from_s;
    if (from_s > l.window.start_s) {
      *error = s.trajectory_path + ": the runs would start at " + fmt("%g", from_s) +
               " s, after their window's start (" + fmt("%g", l.window.start_s) + " s)";
      return false;
    }
    l.window.lead_s =
        std::ceil((l.window.start_s - from_s) / grid.sample_s - 1e-9) * grid.sample_s;
    if (l.window.lead_s > l.window.start_s + 1e-9) l.window.lead_s -= grid.sample_s;
    if (l.window.start_s + l.window.duration_s > l.trajectory.duration_s()) {
      *error = s.trajectory_path + ": the window " + fmt("%g", l.window.start_s) + " s + " +
               fmt("%g", l.window.duration_s) + " s runs past the trajectory's end (" +
               fmt("%g", l.trajectory.duration_s()) + " s)";
      return false;
    }
    rep.windows.emplace_back(s.name, l.window);
    scenes.push_back(std::move(l));
  }
  if (scenes.empty()) {
    *error = "no scene to benchmark";
    return false;
  }

  // Cost weights for the progress display: simulated steps x particles relative to the scene's
  // own lattice (1 per step at the scene's spacing); the peer and the reference are costlier.
  std::vector<Job> jobs;
  for (Loaded& sc : scenes) {
    const WorldConfig& base = sc.world;
    const double h = base.nucleus.spacing_m;
    const double steps = (grid.window_s + sc.window.lead_s) / 1e-3;
    // Reference: the finest step and the tightest tolerance, at the scene's spacing.
    jobs.push_back(
        {sc.scene.name + ": reference " +
             acdr_settings_text(grid.reference_dt_s, grid.reference_tolerance, h),
         steps * (1e-3 / grid.reference_dt_s) * 3.0, [&, h](const auto& progress) {
           RunSettings rs;
           rs.dt_s = grid.reference_dt_s;
           rs.tolerance = grid.reference_tolerance;
           rs.max_iterations = grid.reference_max_iterations;
           rs.nucleus_every = 1;  // the particles at the reference's own step
           rs.pipelined = 0;      // and their reaction in the same step
           // Sleep is a skip: a scene that lets particles sleep nearer the instrument, or
           // moving faster, than the engine's defaults is measured against a reference that
           // does not.
           rs.sleep_distance_m =
               std::max(base.solver.sleep_distance_m, SolverConfig{}.sleep_distance_m);
           rs.sleep_speed_m_s =
               std::min(base.solver.sleep_speed_m_s, SolverConfig{}.sleep_speed_m_s);
           sc.reference = run_scene(apply_settings(base, rs), sc.trajectory, sc.window, progress);
           WorkPoint p = make_point(sc.scene.name, sc.reference, sc.reference);
           p.solver = "acdr";
           p.dt_s = grid.reference_dt_s;
           p.tolerance = grid.reference_tolerance;
           p.spacing_m = h;
           p.settings = acdr_settings_text(p.dt_s, p.tolerance, h) + " (reference)";
           p.is_reference = true;
           rep.points.push_back(p);
         }});
    auto add_acdr = [&, h, steps](double dt, double tol, double spacing, bool is_default,
                                  int pipelined = -1) {
      const double weight =
          steps * (1e-3 / dt) * std::pow(h / spacing, 3.0) * std::max(1, grid.timing_runs);
      jobs.push_back({sc.scene.name + ": acdr " + acdr_settings_text(dt, tol, spacing), weight,
                      [&, dt, tol, spacing, is_default, pipelined](const auto& progress) {
                        RunSettings s;
                        s.dt_s = dt;
                        s.tolerance = tol;
                        s.spacing_m = spacing;
                        s.pipelined = pipelined;
                        if (!is_default && pipelined < 0) s.max_iterations = grid.reference_max_iterations;
                        const WorldConfig config = apply_settings(base, s);
                        const int runs = std::max(1, grid.timing_runs);
                        double slowest_wall_s = 0.0;
                        const RunTrace run = fastest_of(
                            runs,
                            [&](int r) {
                              return run_scene(config, sc.trajectory, sc.window,
                                               [&, r](double f) { progress((r + f) / runs); });
                            },
                            &slowest_wall_s);
                        WorkPoint p = make_point(sc.scene.name, run, sc.reference);
                        p.timing_runs = runs;
                        p.slowest_wall_s_per_sim_s =
                            run.sim_s > 0.0 ? slowest_wall_s / run.sim_s : 0.0;
                        p.solver = "acdr";
                        p.dt_s = dt;
                        p.tolerance = tol;
                        p.spacing_m = spacing;
                        p.settings = acdr_settings_text(dt, tol, spacing) +
                                     nucleus_every_text(config.solver) +
                                     (is_default ? " (default)" : "");
                        p.is_default = is_default;
                        rep.points.push_back(p);
                      }});
    };
    bool has_default = false;
    for (double dt : grid.dts_s)
      for (double tol : grid.tolerances) {
        const bool is_default = std::abs(dt - base.solver.dt_s) < 1e-12 &&
                                std::abs(tol - base.solver.tolerance) < 1e-15;
        has_default = has_default || is_default;
        add_acdr(dt, tol, h, is_default);
      }
    // The scene's own settings, when the grid does not hold them.
    if (!has_default) add_acdr(base.solver.dt_s, base.solver.tolerance, h, true);
    if (sc.scene.spacing_sweep)
      for (double f : grid.spacing_factors)
        add_acdr(base.solver.dt_s, base.solver.tolerance, f * h, false);
    if (sc.scene.pipelined_point)
      add_acdr(base.solver.dt_s, base.solver.tolerance, h, false,
               base.solver.nucleus_pipelined ? 0 : 1);

    // The peer, on the reference's instrument path, at the same lattice (one node per
    // particle, one link per bond).
    const bool peer = grid.peer_on_anatomy || !base.anatomy.enabled;
    const std::vector<int> sweep =
        !peer ? std::vector<int>{}
              : (base.anatomy.enabled ? grid.anatomy_peer_iterations : grid.peer_iterations);
    for (int it : sweep) {
      jobs.push_back(
          {sc.scene.name + ": bullet piterations=" + std::to_string(it),
           steps * (0.3 + 0.1 * it) * (base.anatomy.enabled ? 30.0 : 1.0), [&, it, h](const auto& progress) {
             PeerSettings ps;
             ps.dt_s = 1e-3;
             ps.position_iterations = it;
             ps.link_stiffness = 1.0;
             const RunTrace peer =
                 run_bullet_peer(base, sc.trajectory.at(run_start_s(sc.window, grid.reference_dt_s)),
                                 sc.reference.instrument, sc.window, ps, progress);
             WorkPoint p = make_point(sc.scene.name, peer, sc.reference);
             p.solver = "bullet";
             p.dt_s = ps.dt_s;
             p.iterations = it;
             p.link_stiffness = ps.link_stiffness;
             p.spacing_m = h;
             p.settings = "dt=1ms piterations=" + std::to_string(it) +
                          " kLST=1 h=" + fmt("%g", h * 1e3) + "mm";
             rep.points.push_back(p);
           }});
    }
  }

  // The bone: each load sample of the scene's window solved as the attempt's worker solves it
  // (the scenario's model, meshes from the cache), timed per vertebra solve.
  for (Loaded& sc : scenes) {
    if (!sc.bone.enabled) continue;
    jobs.push_back({sc.scene.name + ": bone solves", grid.window_s / 1e-3 * 1.5,
                    [&](const auto&) {
                      BoneSolveFigures f;
                      const std::vector<BoneLoadRecord> samples =
                          sample_bone_loads(sc.world, sc.trajectory, sc.window);
                      std::string why;
                      std::unique_ptr<BoneSegment> bone;
                      try {
                        const Anatomy anatomy(sc.world.anatomy);
                        bone = BoneSegment::build(anatomy, sc.bone,
                                                  anatomy_cache_dir(sc.world.anatomy, "bone"),
                                                  &why);
                      } catch (const std::exception& e) {
                        why = e.what();
                      }
                      if (bone) {
                        f = time_bone_solves(*bone, samples, std::max(1, grid.timing_runs));
                      } else {
                        f.note = "the bone model could not be built: " + why;
                      }
                      f.scene = sc.scene.name;
                      rep.bone.push_back(f);
                    }});
  }

  // Scaling: cost of a step with every particle awake (the worst case; sleeping far particles
  // is a skip measured below) against particle count, on the first scene, the blade in the
  // material.
  const Loaded& first = scenes.front();
  rep.scaling_scene = first.scene.name;
  std::vector<double> n, cost, per_it;
  for (double spacing : grid.scaling_spacings_m) {
    const int runs = std::max(1, grid.timing_runs);
    const double weight = runs * (double(grid.scaling_warmup_steps + grid.scaling_timed_steps) *
                                      std::pow(first.world.nucleus.spacing_m / spacing, 3.0) *
                                      3.0 +
                                  20.0 * std::pow(1e-3 / spacing, 3.0));  // + the lattice
    jobs.push_back({"scaling: h=" + fmt("%g", spacing * 1e3) + "mm", weight,
                    [&, spacing, runs](const auto&) {
                      RunWindow w;
                      w.start_s = first.window.start_s + 0.1;
                      w.warmup_steps = grid.scaling_warmup_steps;
                      w.duration_s = (grid.scaling_warmup_steps + grid.scaling_timed_steps) *
                                     first.world.solver.dt_s;
                      RunSettings s;
                      s.spacing_m = spacing;
                      s.sleep = 0;
                      s.nucleus_every = 1;  // a particle step at every step: the cost per step
                      // Fastest of `runs`, as the scenes' points: a few steps on a shared host
                      // vary by tens of per cent from run to run.
                      const WorldConfig config = apply_settings(first.world, s);
                      const RunTrace run = fastest_of(
                          runs, [&](int) { return run_scene(config, first.trajectory, w); },
                          nullptr);
                      ScalingPoint p;
                      p.spacing_m = spacing;
                      p.timing_runs = runs;
                      p.particles = run.particles;
                      const double timed = std::max<double>(1.0, double(run.timed_steps));
                      p.wall_ms_per_step = 1e3 * run.wall_s / timed;
                      p.cpu_ms_per_step = 1e3 * run.cpu_s / timed;
                      p.mean_iterations = run.mean_iterations;
                      p.cpu_us_per_particle_step =
                          run.particles > 0
                              ? 1e3 * p.cpu_ms_per_step / double(run.particles)
                              : 0.0;
                      p.p99_step_ms = 1e3 * run.p99_step_wall_s;
                      p.cpu_us_per_iteration_per_particle =
                          run.mean_iterations > 0.0 && run.particles > 0
                              ? 1e3 * p.cpu_ms_per_step / run.mean_iterations /
                                    double(run.particles)
                              : 0.0;
                      rep.scaling.push_back(p);
                      n.push_back(double(run.particles));
                      cost.push_back(p.cpu_ms_per_step);
                      per_it.push_back(p.cpu_ms_per_step / std::max(1.0, run.mean_iterations));
                    }});
  }

  // Skips, on the first scene: each switched off against on (the default); the error is the
  // on-run against the off-run.
  rep.skips_scene = first.scene.name;
  RunWindow skip_window = first.window;
  skip_window.start_s = std::max(0.0, first.window.start_s - grid.skip_lead_s);
  skip_window.lead_s = 0.0;  // the skip runs compare and time their whole run
  skip_window.duration_s = grid.skip_window_s;
  const double skip_weight = grid.skip_window_s / 1e-3 * 0.7;
  RunTrace skip_path;  // the instrument path of a default run (undeclared-parts skip)
  auto add_skip = [&](const std::string& name, const std::string& description,
                      std::function<RunTrace(bool)> run) {
    const std::size_t index = rep.skips.size();
    SkipResult r;
    r.name = name;
    r.description = description;
    rep.skips.push_back(r);
    if (!run) return;
    auto on = std::make_shared<RunTrace>();
    jobs.push_back({"skip " + name + ": on", skip_weight,
                    [&, on, run](const auto&) { *on = run(true); }});
    jobs.push_back({"skip " + name + ": off", skip_weight, [&, on, run, index](const auto&) {
                      const RunTrace off = run(false);
                      SkipResult& s = rep.skips[index];
                      const TraceError e = trace_error(*on, off);
                      s.on_wall_s_per_sim_s = on->wall_s / std::max(1e-12, on->sim_s);
                      s.off_wall_s_per_sim_s = off.wall_s / std::max(1e-12, off.sim_s);
                      s.on_cpu_s_per_sim_s = on->cpu_s / std::max(1e-12, on->sim_s);
                      s.off_cpu_s_per_sim_s = off.cpu_s / std::max(1e-12, off.sim_s);
                      // The renderer's cost is outside this thread's CPU time only partly
                      // (OSMesa runs here, but the driver may not): compare wall time.
                      const bool wall = s.name == "headless";
                      const double on_t = wall ? s.on_wall_s_per_sim_s : s.on_cpu_s_per_sim_s;
                      const double off_t = wall ? s.off_wall_s_per_sim_s : s.off_cpu_s_per_sim_s;
                      s.gain = on_t > 0.0 ? off_t / on_t : 0.0;
                      s.force_rms_error = e.force_rms;
                      s.removed_error = e.removed;
                      s.measured = true;
                    }});
  };
  add_skip("sleep", "particles at rest far from the instrument are not integrated",
           [&](bool on) {
             RunSettings s;
             s.sleep = on ? 1 : 0;
             return run_scene(apply_settings(first.world, s), first.trajectory, skip_window);
           });
  add_skip("contact_culling",
           "particle-collider contacts only where bounding boxes come within reach",
           [&](bool on) {
             WorldConfig c = first.world;
             c.solver.contact_culling = on;
             return run_scene(c, first.trajectory, skip_window);
           });
  // The instrument path of a default run, then the nucleus alone with and without the parts a
  // full anatomy scene would add (they are not built when the scenario does not declare them).
  jobs.push_back({"skip undeclared_parts: instrument path", skip_weight, [&](const auto&) {
                    skip_path = run_scene(first.world, first.trajectory, skip_window);
                  }});
  add_skip("undeclared_parts",
           "parts the scenario does not declare are not built (here: the C4-C5 bodies and "
           "posterior elements beside the box)",
           [&](bool on) {
             return run_nucleus_only(first.world, first.trajectory.at(skip_window.start_s),
                                     skip_path.instrument, skip_window,
                                     on ? std::vector<Collider>{} : undeclared_parts());
           });
  std::function<RunTrace(bool)> headless;
  if (config.render_frame) {
    headless = [&](bool on) {
      if (on) return run_scene(first.world, first.trajectory, skip_window);
      double next_frame = 0.0;
      return run_scene(first.world, first.trajectory, skip_window, {},
                       [&](const World& world, const Frame& f) {
                         if (f.t_s + 1e-9 < next_frame) return;
                         next_frame = f.t_s + 1.0 / 60.0;
                         config.render_frame(world);
                       });
    };
  }
  add_skip("headless", "no renderer when headless (off: a frame drawn offscreen at 60 Hz)",
           headless);

  // Run.
  double total = 0.0, done = 0.0;
  for (const Job& j : jobs) total += j.weight;
  for (const Job& j : jobs) {
    auto progress = [&](double f) {
      if (config.progress) config.progress(j.what, std::min(1.0, (done + f * j.weight) / total));
    };
    progress(0.0);
    j.run(progress);
    done += j.weight;
  }
  rep.scaling_fit = fit_power(n, cost);
  rep.per_iteration_fit = fit_power(n, per_it);

  const std::string end = describe_machine();
  rep.machine += " -> " + end.substr(end.find("load average"));
  rep.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (config.progress) config.progress("done", 1.0);
  return true;
}

}  // namespace acdr
