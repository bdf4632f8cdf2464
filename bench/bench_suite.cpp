// The benchmark suite: work-precision grid, Bullet peer, scaling, skips.
#include "bench/bench_suite.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "bench/trace_error.hpp"
#include "engine/instrument.hpp"
#include "engine/nucleus.hpp"
#include "engine/rigid_world.hpp"
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

/// Tracks the fraction of the benchmark done, by simulated steps weighted by particles.
struct Progress {
  const BenchConfig& config;
  double total = 1.0;
  double done = 0.0;
  std::string what;
  void report(double part) const {
    if (config.progress) config.progress(what, std::min(1.0, (done + part) / total));
  }
};

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
  using Clock = std::chrono::steady_clock;
  RunTrace out;
  std::vector<Collider> statics = build_static_colliders(config);
  statics.insert(statics.end(), extra.begin(), extra.end());
  Nucleus nucleus(config.nucleus, config.solver, config.gravity_m_s2, statics);
  const InstrumentGeometry geometry(config.instrument);
  std::vector<Collider> moving;
  moving.reserve(geometry.local_colliders().size());
  std::vector<BodyReaction> reactions(1);
  const double dt = config.solver.dt_s;
  const double duration = window.duration_s > 0.0 ? window.duration_s
                                                  : window.sample_s * double(path.size());
  const auto steps = static_cast<std::int64_t>(std::llround(duration / dt));
  const auto windows = static_cast<std::size_t>(std::floor(duration / window.sample_s + 1e-9));
  out.particles = nucleus.particle_count();
  out.bonds = nucleus.bond_count();
  Vec3 f_sum = Vec3::Zero();
  int f_count = 0;
  const auto t0 = Clock::now();
  const double c0 = thread_cpu_s();
  for (std::int64_t k = 0; k < steps; ++k) {
    const double t = double(k) * dt;
    const Pose now = pose_on_path(start, path, window.sample_s, t);
    const Pose next = pose_on_path(start, path, window.sample_s, t + dt);
    const Vec3 v = (next.position - now.position) / dt;
    Quat dq = next.orientation * now.orientation.conjugate();
    if (dq.w() < 0) dq.coeffs() *= -1.0;
    const Eigen::AngleAxisd aa(dq);
    geometry.world_colliders(now, v, aa.axis() * (aa.angle() / dt), moving);
    reactions[0] = BodyReaction{};
    reactions[0].reference_point = now.position;
    NumericalReport report;
    nucleus.step(dt, moving, reactions, report);
    out.mean_iterations += report.iterations;
    out.mean_active += static_cast<double>(nucleus.active_count());
    if (!report.ok) out.failed = true;
    f_sum += reactions[0].force_N;
    ++f_count;
    const double t_rel = double(k + 1) * dt;
    const double boundary = double(out.t_s.size() + 1) * window.sample_s;
    if (out.t_s.size() < windows && t_rel >= boundary - 1e-9 * dt) {
      out.t_s.push_back(boundary);
      out.force_N.push_back(f_sum / f_count);
      f_sum = Vec3::Zero();
      f_count = 0;
    }
  }
  out.cpu_s = thread_cpu_s() - c0;
  out.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  out.steps = out.timed_steps = steps;
  out.sim_s = double(steps) * dt;
  if (steps > 0) {
    out.mean_iterations /= double(steps);
    out.mean_active /= double(steps);
  }
  out.state_hash = nucleus.state_hash();
  return out;
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
  out << model << ", " << cpus << " logical CPUs, load average " << load.substr(0, 14);
  return out.str();
}

bool run_bench_suite(const BenchConfig& config, BenchReport* report, std::string* error) {
  const auto t_start = std::chrono::steady_clock::now();
  BenchReport& rep = *report;
  rep = BenchReport{};
  rep.machine = describe_machine();
  const bool quick = config.quick;

  // Scenes.
  struct Loaded {
    BenchScene scene;
    WorldConfig world;
    Trajectory trajectory;
  };
  std::vector<Loaded> scenes;
  for (const BenchScene& s : config.scenes) {
    const LoadResult loaded = load_scenario_file(s.scenario_path);
    if (!loaded.ok()) {
      *error = s.scenario_path + ": cannot load the scenario";
      if (!loaded.errors.empty()) *error = loaded.errors.front().to_string();
      return false;
    }
    auto trajectory = Trajectory::load_csv(s.trajectory_path, error);
    if (!trajectory) return false;
    Loaded l{s, loaded.model->world, std::move(*trajectory)};
    // Quick: a coarser lattice of the same scene (fewer particles, same geometry and motion).
    if (quick) l.world.nucleus.spacing_m = std::max(l.world.nucleus.spacing_m, 2.0e-3);
    scenes.push_back(std::move(l));
  }
  if (scenes.empty()) {
    *error = "no scene to benchmark";
    return false;
  }

  // The window: the blade entering the material and digging (the costly, force-carrying part
  // of a scoop). The box demo's first contact is at ~1.9 s.
  RunWindow window;
  window.start_s = quick ? 1.85 : 1.8;
  window.duration_s = quick ? 0.4 : 1.5;
  window.sample_s = 0.01;
  rep.window = window;

  // Grid.
  const double ref_dt = 0.5e-3;
  const double ref_tol = quick ? 1e-6 : 1e-7;
  std::vector<double> dts = quick ? std::vector<double>{1e-3, 2e-3}
                                  : std::vector<double>{0.5e-3, 1e-3, 2e-3};
  std::vector<double> tols = {1e-2, 1e-3, 1e-4};
  if (!quick) tols.push_back(1e-5);
  std::vector<double> coarser = quick ? std::vector<double>{} : std::vector<double>{1.5e-3, 2e-3};
  std::vector<int> peer_iters = quick ? std::vector<int>{2, 8} : std::vector<int>{1, 2, 4, 8, 16};

  // Progress weights: simulated steps x particles, roughly.
  Progress progress{config, 1.0, 0.0, {}};
  const double window_steps = window.duration_s / 1e-3;
  progress.total = double(scenes.size()) *
                       (window_steps * (1e-3 / ref_dt) * 3.0 +
                        window_steps * double(dts.size() * tols.size() + coarser.size()) +
                        0.3 * window_steps * double(peer_iters.size())) +
                   (quick ? 8.0 : 20.0) * window_steps + (quick ? 0.5 : 3.0) * window_steps;

  for (const Loaded& sc : scenes) {
    const WorldConfig& base = sc.world;
    const double h = base.nucleus.spacing_m;
    // Reference: the finest step and a tight tolerance.
    RunSettings ref_settings;
    ref_settings.dt_s = ref_dt;
    ref_settings.tolerance = ref_tol;
    ref_settings.max_iterations = 2000;
    progress.what = sc.scene.name + ": reference " + acdr_settings_text(ref_dt, ref_tol, h);
    const RunTrace reference =
        run_scene(apply_settings(base, ref_settings), sc.trajectory, window,
                  [&](double f) { progress.report(f * window_steps * 3.0 * (1e-3 / ref_dt)); });
    progress.done += window_steps * 3.0 * (1e-3 / ref_dt);
    {
      WorkPoint p = make_point(sc.scene.name, reference, reference);
      p.solver = "acdr";
      p.dt_s = ref_dt;
      p.tolerance = ref_tol;
      p.spacing_m = h;
      p.settings = acdr_settings_text(ref_dt, ref_tol, h) + " (reference)";
      p.is_reference = true;
      rep.points.push_back(p);
    }
    auto add_acdr = [&](double dt, double tol, double spacing, bool is_default) {
      RunSettings s;
      s.dt_s = dt;
      s.tolerance = tol;
      s.spacing_m = spacing;
      if (!is_default) s.max_iterations = 2000;
      progress.what = sc.scene.name + ": acdr " + acdr_settings_text(dt, tol, spacing);
      const RunTrace run = run_scene(apply_settings(base, s), sc.trajectory, window,
                                     [&](double f) { progress.report(f * window_steps); });
      progress.done += window_steps;
      WorkPoint p = make_point(sc.scene.name, run, reference);
      p.solver = "acdr";
      p.dt_s = dt;
      p.tolerance = tol;
      p.spacing_m = spacing;
      p.settings = acdr_settings_text(dt, tol, spacing) + (is_default ? " (default)" : "");
      p.is_default = is_default;
      rep.points.push_back(p);
    };
    for (double dt : dts)
      for (double tol : tols) {
        const bool is_default = std::abs(dt - base.solver.dt_s) < 1e-12 &&
                                std::abs(tol - base.solver.tolerance) < 1e-15;
        add_acdr(dt, tol, h, is_default);
      }
    // The scene's own settings, when the grid does not hold them.
    bool has_default = false;
    for (const WorkPoint& p : rep.points) has_default = has_default || (p.is_default && p.scene == sc.scene.name);
    if (!has_default) add_acdr(base.solver.dt_s, base.solver.tolerance, h, true);
    for (double spacing : coarser) add_acdr(base.solver.dt_s, base.solver.tolerance, spacing, false);

    // The peer, on the reference's instrument path.
    for (int it : peer_iters) {
      PeerSettings ps;
      ps.dt_s = 1e-3;
      ps.position_iterations = it;
      ps.link_stiffness = 1.0;
      progress.what = sc.scene.name + ": bullet piterations=" + std::to_string(it);
      const RunTrace peer = run_bullet_peer(
          base, sc.trajectory.at(window.start_s), reference.instrument, window, ps,
          [&](double f) { progress.report(f * 0.3 * window_steps); });
      progress.done += 0.3 * window_steps;
      WorkPoint p = make_point(sc.scene.name, peer, reference);
      p.solver = "bullet";
      p.dt_s = ps.dt_s;
      p.iterations = it;
      p.link_stiffness = ps.link_stiffness;
      p.spacing_m = h;
      p.settings = "dt=1ms piterations=" + std::to_string(it) + " kLST=1 h=" + fmt("%g", h * 1e3) + "mm";
      rep.points.push_back(p);
    }
  }

  // Scaling: cost of a step with every particle awake (the worst case; sleeping far particles
  // is a skip measured below) against particle count, on the first scene.
  {
    const Loaded& sc = scenes.front();
    rep.scaling_scene = sc.scene.name;
    const std::vector<double> spacings =
        quick ? std::vector<double>{2.0e-3, 1.5e-3, 1.2e-3, 1.0e-3}
              : std::vector<double>{1.7e-3, 1.25e-3, 1.0e-3, 0.8e-3, 0.62e-3, 0.46e-3};
    RunWindow w;
    w.start_s = 2.0;
    w.warmup_steps = 5;
    const int timed = quick ? 10 : 30;
    w.duration_s = (w.warmup_steps + timed) * sc.world.solver.dt_s;
    std::vector<double> n, cost, per_it;
    for (double spacing : spacings) {
      RunSettings s;
      s.spacing_m = spacing;
      s.sleep = 0;
      progress.what = "scaling: h=" + fmt("%g", spacing * 1e3) + "mm";
      progress.report(0.0);
      const RunTrace run = run_scene(apply_settings(sc.world, s), sc.trajectory, w);
      progress.done += (quick ? 2.0 : 5.0) * window_steps / double(spacings.size());
      ScalingPoint p;
      p.spacing_m = spacing;
      p.particles = run.particles;
      const double steps = std::max<double>(1.0, double(run.timed_steps));
      p.wall_ms_per_step = 1e3 * run.wall_s / steps;
      p.cpu_ms_per_step = 1e3 * run.cpu_s / steps;
      p.mean_iterations = run.mean_iterations;
      p.cpu_us_per_iteration_per_particle =
          run.mean_iterations > 0.0 && run.particles > 0
              ? 1e3 * p.cpu_ms_per_step / run.mean_iterations / double(run.particles)
              : 0.0;
      rep.scaling.push_back(p);
      n.push_back(double(run.particles));
      cost.push_back(p.cpu_ms_per_step);
      per_it.push_back(p.cpu_ms_per_step / std::max(1.0, run.mean_iterations));
    }
    rep.scaling_fit = fit_power(n, cost);
    rep.per_iteration_fit = fit_power(n, per_it);
  }

  // Skips, on the first scene: each switched off against on (the default); the error is the
  // on-run against the off-run.
  {
    const Loaded& sc = scenes.front();
    rep.skips_scene = sc.scene.name;
    RunWindow w = window;
    // Sleeping needs time to matter: start while the instrument is still above the material.
    w.start_s = quick ? 1.4 : 1.0;
    w.duration_s = quick ? 0.9 : 2.5;
    const double w_steps = w.duration_s / 1e-3;
    const double share = (quick ? 8.0 : 20.0) * window_steps / 8.0;
    auto run_pair = [&](SkipResult& r, const std::function<RunTrace(bool)>& run) {
      progress.what = "skip " + r.name + ": on";
      progress.report(0.0);
      const RunTrace on = run(true);
      progress.done += share;
      progress.what = "skip " + r.name + ": off";
      progress.report(0.0);
      const RunTrace off = run(false);
      progress.done += share;
      const TraceError e = trace_error(on, off);
      r.on_wall_s_per_sim_s = on.wall_s / std::max(1e-12, on.sim_s);
      r.off_wall_s_per_sim_s = off.wall_s / std::max(1e-12, off.sim_s);
      r.on_cpu_s_per_sim_s = on.cpu_s / std::max(1e-12, on.sim_s);
      r.off_cpu_s_per_sim_s = off.cpu_s / std::max(1e-12, off.sim_s);
      r.gain = r.on_cpu_s_per_sim_s > 0.0 ? r.off_cpu_s_per_sim_s / r.on_cpu_s_per_sim_s : 0.0;
      if (r.name == "headless")
        r.gain = r.on_wall_s_per_sim_s > 0.0 ? r.off_wall_s_per_sim_s / r.on_wall_s_per_sim_s : 0.0;
      r.force_rms_error = e.force_rms;
      r.removed_error = e.removed;
      r.measured = true;
    };
    (void)w_steps;
    {
      SkipResult r;
      r.name = "sleep";
      r.description = "particles at rest far from the instrument are not integrated";
      run_pair(r, [&](bool on) {
        RunSettings s;
        s.sleep = on ? 1 : 0;
        return run_scene(apply_settings(sc.world, s), sc.trajectory, w);
      });
      rep.skips.push_back(r);
    }
    {
      SkipResult r;
      r.name = "contact_culling";
      r.description = "particle-collider contacts only where bounding boxes come within reach";
      run_pair(r, [&](bool on) {
        WorldConfig c = sc.world;
        c.solver.contact_culling = on;
        return run_scene(c, sc.trajectory, w);
      });
      rep.skips.push_back(r);
    }
    {
      // The instrument path of a default run, then the nucleus alone with and without the
      // parts a full anatomy scene would add.
      SkipResult r;
      r.name = "undeclared_parts";
      r.description = "parts the scenario does not declare are not built (here: the C4-C5 "
                      "bodies and posterior elements beside the box)";
      const RunTrace path = run_scene(sc.world, sc.trajectory, w);
      const std::vector<Collider> extra = undeclared_parts();
      run_pair(r, [&](bool on) {
        return run_nucleus_only(sc.world, sc.trajectory.at(w.start_s), path.instrument, w,
                                on ? std::vector<Collider>{} : extra);
      });
      rep.skips.push_back(r);
    }
    {
      SkipResult r;
      r.name = "headless";
      r.description = "no renderer when headless (off: a frame drawn offscreen at 60 Hz)";
      if (config.render_frame) {
        run_pair(r, [&](bool on) {
          if (on) return run_scene(sc.world, sc.trajectory, w);
          double next_frame = 0.0;
          return run_scene(sc.world, sc.trajectory, w, {},
                           [&](const World& world, const Frame& f) {
                             if (f.t_s + 1e-9 < next_frame) return;
                             next_frame = f.t_s + 1.0 / 60.0;
                             config.render_frame(world);
                           });
        });
      }
      rep.skips.push_back(r);
    }
  }
  rep.machine += " -> " + describe_machine().substr(describe_machine().find("load average"));
  rep.wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  if (config.progress) config.progress("done", 1.0);
  return true;
}

}  // namespace acdr
