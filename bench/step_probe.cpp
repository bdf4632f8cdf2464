// acdr_step_probe: times the World step on a scenario along a trajectory and prints the
// figures to compare before/after a solver change (ms per step and per stage, PCG iterations,
// active particles, force checksum, state hash). A development tool, not a test.
//   acdr_step_probe SCENARIO TRAJECTORY [duration_s] [spacing_mm] [tol] [max_it] [start_s] [sleep]
// Environment: ACDR_PROBE_DT_MS (the step, ms), ACDR_PROBE_LEAD_S (simulated time run before
// start_s, neither timed nor traced; a whole number of force windows), ACDR_PROBE_SAMPLE_S (the
// force windows, s; default RunWindow's), ACDR_PROBE_TRACE (a CSV file for the force trace).
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench/bullet_peer.hpp"
#include "bench/scene_run.hpp"
#include "bench/trace_error.hpp"
#include "scenarios/scenario_loader.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s SCENARIO TRAJECTORY [duration_s] [spacing_mm] [tol] [max_it]\n",
                 argv[0]);
    return 2;
  }
  const auto loaded = acdr::load_scenario_file(argv[1]);
  if (!loaded.ok()) {
    std::fprintf(stderr, "cannot load %s\n", argv[1]);
    return 1;
  }
  std::string error;
  const auto trajectory = acdr::Trajectory::load_csv(argv[2], &error);
  if (!trajectory) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  const double duration = argc > 3 ? std::atof(argv[3]) : 0.0;
  acdr::RunSettings s;
  if (argc > 4) s.spacing_m = std::atof(argv[4]) * 1e-3;
  if (argc > 5) s.tolerance = std::atof(argv[5]);
  if (argc > 6) s.max_iterations = std::atoi(argv[6]);
  acdr::RunWindow window;
  window.duration_s = duration;
  if (argc > 7) window.start_s = std::atof(argv[7]);
  if (argc > 8) s.sleep = std::atoi(argv[8]);
  if (const char* dt_ms = std::getenv("ACDR_PROBE_DT_MS")) s.dt_s = std::atof(dt_ms) * 1e-3;
  if (const char* lead = std::getenv("ACDR_PROBE_LEAD_S")) window.lead_s = std::atof(lead);
  if (const char* sample = std::getenv("ACDR_PROBE_SAMPLE_S")) window.sample_s = std::atof(sample);
  const acdr::WorldConfig config = acdr::apply_settings(loaded.model->world, s);
  const acdr::RunTrace r = acdr::run_scene(config, *trajectory, window);
  double f_sum = 0.0, f_max = 0.0;
  for (const acdr::Vec3& fv : r.force_N) {
    const double f = fv.norm();
    f_sum += f;
    if (f > f_max) f_max = f;
  }
  std::printf("particles %zu bonds %zu steps %lld sim %.3f s wall %.3f s -> %.4f ms/step "
              "(%.3fx real time, slowest step %.2f ms, p99 %.2f ms)%s\n",
              r.particles, r.bonds, static_cast<long long>(r.steps), r.sim_s, r.wall_s,
              1e3 * r.wall_s / std::max<long long>(1, r.steps), r.sim_s / r.wall_s,
              1e3 * r.max_step_wall_s, 1e3 * r.p99_step_wall_s, r.failed ? " FAILED" : "");
  std::printf("cpu %.3f s -> %.4f ms/step CPU\n", r.cpu_s,
              1e3 * r.cpu_s / std::max<long long>(1, r.steps));
  std::printf("mean iterations %.2f, mean active %.0f, removed %d (%.4f), mean |F| %.6f N, "
              "peak |F| %.6f N, hash %016llx\n",
              r.mean_iterations, r.mean_active, r.removed_target, r.removed_fraction,
              r.force_N.empty() ? 0.0 : f_sum / r.force_N.size(), f_max,
              static_cast<unsigned long long>(r.state_hash));
  if (const char* path = std::getenv("ACDR_PROBE_TRACE")) {
    // Force windows as CSV, for comparing two builds or settings.
    if (FILE* f = std::fopen(path, "w")) {
      std::fprintf(f, "t_s,fx_N,fy_N,fz_N\n");
      for (std::size_t k = 0; k < r.force_N.size(); ++k)
        std::fprintf(f, "%.6f,%.9e,%.9e,%.9e\n", r.t_s[k], r.force_N[k].x(), r.force_N[k].y(),
                     r.force_N[k].z());
      std::fclose(f);
    }
  }
  std::printf("stages ms/step:");
  for (int k = 0; k < static_cast<int>(acdr::StepStage::kCount); ++k)
    std::printf(" %s %.4f", acdr::step_stage_name(static_cast<acdr::StepStage>(k)),
                1e3 * r.stages.seconds[k] / std::max<std::int64_t>(1, r.stages.steps));
  std::printf("\n");
  if (argc > 9) {
    // Peer on our run's instrument path, compared with our run.
    acdr::PeerSettings ps;
    ps.position_iterations = std::atoi(argv[9]);
    if (argc > 10) ps.link_stiffness = std::atof(argv[10]);
    if (argc > 11) ps.damping = std::atof(argv[11]);
    const acdr::RunTrace peer = acdr::run_bullet_peer(
        config, trajectory->at(acdr::run_start_s(window, config.solver.dt_s)), r.instrument, window, ps);
    const acdr::TraceError e = acdr::trace_error(peer, r);
    std::printf("peer: %zu nodes %zu links, cpu %.3f s -> %.4f ms/step, force rms err %.3f "
                "peak err %.3f, removed %.4f%s\n",
                peer.particles, peer.bonds, peer.cpu_s, 1e3 * peer.cpu_s / peer.steps,
                e.force_rms, e.force_peak, peer.removed_fraction, peer.failed ? " FAILED" : "");
    for (std::size_t k = 0; k < peer.force_N.size(); k += 10)
      std::printf("  t %.2f ours %.4f peer %.4f\n", peer.t_s[k], r.force_N[k].norm(),
                  peer.force_N[k].norm());
  }
  return r.failed ? 1 : 0;
}
