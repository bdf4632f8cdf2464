// The `acdr` program: parses arguments and calls the libraries. Nothing else lives here.
#include <CLI/CLI.hpp>

#include <iostream>

#include "app/allocation_guard.hpp"
#include "cli/bench_command.hpp"
#include "cli/calibrate_command.hpp"
#include "cli/dashboard_command.hpp"
#include "cli/device_sim_command.hpp"
#include "cli/make_trajectory_command.hpp"
#include "cli/render_command.hpp"
#include "cli/report_command.hpp"
#include "cli/rescore_command.hpp"
#include "cli/send_command.hpp"
#include "cli/run_command.hpp"
#include "cli/stress_command.hpp"
#include "cli/validate_command.hpp"
#include "cli/verify_command.hpp"


int main(int argc, char** argv) {
  CLI::App app{"ACDR Trainer: scooping simulation and assessment for artificial cervical disc "
               "replacement"};
  app.require_subcommand(1);
  app.set_version_flag("--version", ACDR_VERSION_STRING " (SIMD path " ACDR_SIMD_PATH ")");
  int code = 0;

  // acdr run
  acdr::RunOptions run;
  auto* run_cmd = app.add_subcommand("run", "Run one attempt of a scenario (module)");
  run_cmd->add_option("scenario", run.scenario, "Scenario file (JSON)")->required();
  run_cmd->add_option("--input", run.input,
                      "replay:FILE (a recorded trajectory, CSV), udp:PORT (a haptic device "
                      "bridge, docs/haptic-bridge.md) or mouse (window only)")
      ->required();
  run_cmd->add_option("--trainee", run.trainee, "Trainee id (omit for a practice attempt)");
  run_cmd->add_flag("--override", run.override_lock,
                    "Let the trainee take a locked module (an instructor's decision, recorded)");
  run_cmd->add_option("--override-by", run.override_by, "Who allowed the override");
  run_cmd->add_option("--override-reason", run.override_reason, "Why");
  run_cmd->add_option("--db", run.db, "Database file (default: $ACDR_DB or the data directory)");
  run_cmd->add_option("--curriculum", run.curriculum_dir,
                      "Folder of the curriculum's scenario files (default: the scenario's own "
                      "folder); all are registered so prerequisites hold from the first attempt");
  run_cmd->add_option("--png", run.png, "Write a picture of the final frame");
  run_cmd->add_option("--record", run.record, "Also write the attempt's recording to a file");
  run_cmd->add_flag("--json", run.json, "Print the result as JSON on stdout");
  run_cmd->add_flag("--beads", run.beads,
                    "Draw the nucleus, annulus and cartilage as their particles (beads), a "
                    "debug view, instead of surfaces (window and --png)");
  run_cmd->add_flag("--headless", run.headless,
                    "No window (default: a window when a display exists)");
  run_cmd->add_option("--device-timeout", run.device_timeout_s,
                      "udp: seconds to wait for the bridge, and without packets before the "
                      "attempt ends as disconnected (default 5)")
      ->check(CLI::PositiveNumber);
  run_cmd->add_option("--checkpoint-every", run.checkpoint_every_s,
                      "Save the attempt so far every this many simulated seconds, so a "
                      "killed run keeps it (default 5; 0: never); live runs write it on a "
                      "thread of their own")
      ->check(CLI::NonNegativeNumber);
  run_cmd->add_option("--store-wait", run.store_patience_s,
                      "Seconds to keep trying when the record cannot be written at the end "
                      "(locked by another program, disk full) before keeping the result in "
                      "a side file next to the database (default 10)")
      ->check(CLI::NonNegativeNumber);
  run_cmd->add_flag("--realtime", run.realtime,
                    "Ask for real-time priority for the haptic loop (needs the privilege)");
  run_cmd->add_option("--lrs-config", run.lrs_config,
                      "LRS configuration file: IRI base of the queued statements, and sending "
                      "after the attempt when it says so (default: $ACDR_LRS_CONFIG or "
                      "~/.config/acdr/lrs.json, and the environment)");
  run_cmd->add_option("--screenshot", run.screenshot,
                      "Window: save a picture of the trainee view (PNG)");
  run_cmd->add_option("--screenshot-at", run.screenshot_at_s,
                      "Window: simulated time of that picture in s (default: the last frame)");
  run_cmd->add_option("--score-screenshot", run.score_screenshot,
                      "Window: save a picture of the score screen (PNG)");
  run_cmd->add_option("--close-after", run.close_after_s,
                      "Window: close the score screen after this many seconds");
  run_cmd->add_flag("--stress-view", run.stress_view,
                    "Window: start with the bone stress view on (key B toggles it; scenes that "
                    "model the bone)");
  run_cmd->callback([&] { code = acdr::run_run(run, std::cout, std::cerr); });

  // acdr dashboard
  acdr::DashboardOptions dash;
  auto* dash_cmd = app.add_subcommand("dashboard", "The instructor dashboard");
  dash_cmd->add_option("--db", dash.db, "Database file (default: $ACDR_DB or the data directory)");
  dash_cmd->add_option("--screenshot", dash.screenshot,
                       "Render one frame offscreen to this PNG and exit");
  dash_cmd->add_option("--export-csv", dash.export_csv,
                       "Write the selected view's CSV to this file and exit");
  dash_cmd->add_option("--width", dash.width, "Width in pixels")->check(CLI::Range(320, 8192));
  dash_cmd->add_option("--height", dash.height, "Height in pixels")->check(CLI::Range(240, 8192));
  dash_cmd->add_option("--trainee", dash.trainee, "Select this trainee");
  dash_cmd->add_option("--module", dash.module, "Learning curve of this module");
  dash_cmd->add_option("--attempt", dash.attempt, "Open this attempt (0: none)");
  dash_cmd->add_option("--replay-t", dash.replay_t_s, "Replay cursor time (s)");
  dash_cmd->add_option("--export-dir", dash.export_dir,
                       "Where the window's Export CSV button writes (default .)");
  dash_cmd->callback([&] { code = acdr::run_dashboard(dash, std::cout, std::cerr); });

  // acdr device-sim
  acdr::DeviceSimOptions sim;
  auto* sim_cmd = app.add_subcommand(
      "device-sim", "A virtual haptic device: plays a trajectory over the UDP bridge protocol");
  sim_cmd->add_option("--port", sim.bridge.port, "The simulator's UDP port (acdr run --input "
                                                  "udp:PORT)")
      ->required()
      ->check(CLI::Range(1, 65535));
  sim_cmd->add_option("--trajectory", sim.trajectory, "Trajectory CSV to play")->required();
  sim_cmd->add_option("--host", sim.bridge.host, "The simulator's address (default 127.0.0.1)");
  sim_cmd->add_option("--rate", sim.bridge.rate_hz, "Pose packets per second (default 1000)")
      ->check(CLI::Range(1.0, 20000.0));
  sim_cmd->add_option("--forces-csv", sim.forces_csv, "Log the forces received to a CSV file");
  sim_cmd->add_option("--connect-timeout", sim.bridge.connect_timeout_s,
                      "Seconds to wait for the simulator to answer (default 30)");
  sim_cmd->add_option("--peer-timeout", sim.bridge.peer_timeout_s,
                      "Seconds without a force from the simulator, once playing, after which "
                      "it counts as gone (default 5; exit code 1)")
      ->check(CLI::PositiveNumber);
  sim_cmd->add_option("--drop-every", sim.bridge.drop_every,
                      "Fault: withhold every n-th pose packet");
  sim_cmd->add_option("--silence-at", sim.bridge.silence_at_s,
                      "Fault: stop sending at this trajectory time (s) ...");
  sim_cmd->add_option("--silence-for", sim.bridge.silence_for_s, "... for this long (s)");
  sim_cmd->add_option("--nan-at", sim.bridge.nan_at_s, "Fault: one NaN pose at this time (s)");
  sim_cmd->add_option("--jump-at", sim.bridge.jump_at_s,
                      "Fault: poses jump by --jump-mm along x from this time (s) for 20 ms");
  double jump_mm = 50.0;
  sim_cmd->add_option("--jump-mm", jump_mm, "Size of that jump (mm, default 50)");
  sim_cmd->add_flag("--realtime", sim.bridge.realtime_priority,
                    "Ask for real-time priority for the send loop (needs the privilege)");
  sim_cmd->add_flag("--json", sim.json, "Print the summary as JSON");
  sim_cmd->callback([&] {
    sim.bridge.jump_m = jump_mm * 1e-3;
    code = acdr::run_device_sim(sim, std::cout, std::cerr);
  });

  // acdr validate
  std::vector<std::string> validate_files;
  auto* validate_cmd = app.add_subcommand("validate", "Check scenario files");
  validate_cmd->add_option("files", validate_files, "Scenario files")->required();
  validate_cmd->callback([&] { code = acdr::run_validate(validate_files, std::cout); });

  // acdr report
  acdr::ReportOptions report;
  auto* report_cmd = app.add_subcommand("report", "Attempts and progress from the database");
  report_cmd->add_option("--db", report.db_path, "Database file");
  report_cmd->add_option("--trainee", report.trainee, "Only this trainee");
  report_cmd->add_option("--module", report.module, "Only this module");
  report_cmd->add_option("--format", report.format, "table, csv, json or xapi")
      ->check(CLI::IsMember({"table", "csv", "json", "xapi"}));
  report_cmd->add_option("--config", report.lrs_config,
                         "xapi: LRS configuration file for the activity IRI base (default: "
                         "$ACDR_LRS_CONFIG or ~/.config/acdr/lrs.json; ACDR_XAPI_IRI_BASE wins)");
  report_cmd->callback([&] { code = acdr::run_report(report, std::cout, std::cerr); });

  // acdr send
  acdr::SendOptions send;
  auto* send_cmd = app.add_subcommand(
      "send", "Send the record's queued xAPI statements to the learning record store");
  send_cmd->add_option("--db", send.db_path, "Database file");
  send_cmd->add_option("--config", send.config,
                       "LRS configuration file (default: $ACDR_LRS_CONFIG or "
                       "~/.config/acdr/lrs.json; ACDR_LRS_ENDPOINT, ACDR_LRS_KEY, "
                       "ACDR_LRS_SECRET, ACDR_XAPI_IRI_BASE override it)");
  send_cmd->add_option("--retry-for", send.retry_for_s,
                       "Seconds to keep retrying (with doubling pauses) while the store cannot "
                       "be reached (default 60; 0: one try)")
      ->check(CLI::NonNegativeNumber);
  send_cmd->add_flag("--queue-existing", send.queue_existing,
                     "First queue the statements of stored attempts that are not in the "
                     "outbox yet (records from before it)");
  send_cmd->add_flag("--retry-failed", send.retry_failed,
                     "First queue again the statements the store refused");
  send_cmd->callback([&] { code = acdr::run_send(send, std::cout, std::cerr); });

  // acdr verify
  acdr::VerifyOptions verify;
  auto* verify_cmd = app.add_subcommand(
      "verify", "Analytic verification of the physics (seed Eq. 1-11 and more)");
  verify_cmd->add_option("cases", verify.case_files, "Case files (JSON); none: built-in cases");
  verify_cmd->add_flag("--json", verify.json, "Print the results as JSON");
  verify_cmd->add_flag("--fast", verify.fast, "Smaller scenes, same tolerances");
  verify_cmd->callback([&] { code = acdr::run_verify(verify, std::cout, std::cerr); });

  // acdr stress
  acdr::StressOptions stress;
  auto* stress_cmd = app.add_subcommand(
      "stress", "Numerical stability suite: time step, stiffness, viscosity, speed, bad input");
  stress_cmd->add_flag("--json", stress.json, "Print the results as JSON");
  stress_cmd->add_flag("--fast", stress.fast, "Coarser particles and shorter holds");
  stress_cmd->callback([&] { code = acdr::run_stress(stress, std::cout, std::cerr); });

  // --- acdr bench ---
  acdr::BenchOptions bench;
  auto* bench_cmd = app.add_subcommand(
      "bench", "Work-precision benchmark: run time against error, Bullet soft-body peer, "
               "scaling with particle count, skips");
  bench_cmd->add_flag("--quick", bench.quick, "Small grid and the scenes' quick references (about 3 minutes on two cores)");
  bench_cmd->add_option("--csv", bench.csv, "Also write every figure as CSV");
  bench_cmd->add_flag("--json", bench.json, "Print the results as JSON");
  bench_cmd->add_option("--png", bench.png, "Work-precision plot (PNG; empty string: none)");
  bench_cmd->add_option("--scene", bench.scenes,
                        "NAME=SCENARIO.json:TRAJECTORY.csv[@WINDOW_START_S[,RUN_FROM_S]]: runs start at RUN_FROM_S "
                        "(default 0: the trajectory's start) and are compared and timed from WINDOW_START_S "
                        "(default: the box and healthy C4-C5 modules)");
  bench_cmd->callback([&] { code = acdr::run_bench(bench, std::cout, std::cerr); });

  // acdr render
  acdr::RenderOptions render;
  auto* render_cmd = app.add_subcommand("render", "Offscreen picture of a scenario's scene");
  render_cmd->add_option("scenario", render.scenario, "Scenario file (JSON)")->required();
  render_cmd->add_option("--png", render.png, "Output PNG")->required();
  render_cmd->add_option("--width", render.width, "Width in pixels");
  render_cmd->add_option("--height", render.height, "Height in pixels");
  render_cmd->add_option("--view", render.view,
                         "Anatomy: surgeon (default), anterior or lateral (the whole segment)");
  render_cmd->add_flag("--labels", render.labels, "Name the parts on the picture (anterior, lateral)");
  render_cmd->add_flag("--beads", render.beads,
                       "Draw the particle materials as beads (a debug view) instead of surfaces");
  render_cmd->add_option("--stress-load", render.stress_loads,
                         "Draw the bone's stress under this load instead: x,y,z,fx,fy,fz (mm, N, "
                         "segment frame, force on the bone); repeat for several");
  render_cmd->add_option("--stress-radius", render.stress_radius_mm,
                         "Patch radius of --stress-load (mm, default 1)");
  render_cmd->add_option("--recording", render.recording,
                         "Draw the bone's stress under a recorded attempt's loads (a file written "
                         "by acdr run --record)");
  render_cmd->add_option("--attempt", render.attempt,
                         "... or a stored attempt's loads (id in the database)");
  render_cmd->add_option("--db", render.db, "Database file for --attempt");
  render_cmd->add_option("--at", render.at_s,
                         "Time in the attempt (s; default: its moment of peak bone load)");
  render_cmd->add_option("--stress-max", render.stress_max_MPa,
                         "Top of the colour bar (MPa; default: the peak, rounded up)");
  render_cmd->callback([&] { code = acdr::run_render(render, std::cout, std::cerr); });

  // acdr rescore
  acdr::RescoreOptions rescore;
  auto* rescore_cmd =
      app.add_subcommand("rescore", "Re-score stored attempts from their recordings");
  rescore_cmd->add_option("--db", rescore.db, "Database file");
  rescore_cmd->add_option("--trainee", rescore.trainee, "Only this trainee's attempts");
  rescore_cmd->add_option("--module", rescore.module, "Only attempts at this module");
  rescore_cmd->add_option("--attempt", rescore.attempt, "Only this attempt id");
  rescore_cmd->add_flag("--dry-run", rescore.dry_run, "Compute and print, store nothing");
  rescore_cmd->callback([&] { code = acdr::run_rescore(rescore, std::cout, std::cerr); });

  // acdr calibrate
  acdr::CalibrateOptions calibrate;
  auto* calibrate_cmd = app.add_subcommand(
      "calibrate",
      "Set a module's rubric benchmarks from an expert cohort: per metric the experts' (trimmed) "
      "mean and SD (docs/assessment.md, Calibration)");
  calibrate_cmd->add_option("scenario", calibrate.scenario, "Module file (JSON)")->required();
  auto* record_opt = calibrate_cmd->add_option(
      "--record", calibrate.records,
      "Training record (database file) holding the experts' attempts (repeat to pool records)");
  calibrate_cmd->add_option("--trainee", calibrate.trainees,
                            "With --record: only this trainee's attempts (repeat for each "
                            "expert; default: every completed attempt at the module)")
      ->needs(record_opt);
  auto* demos_opt = calibrate_cmd->add_option(
      "--demonstrations", calibrate.demonstrations,
      "Folder of expert demonstrations (expert_*.csv), replayed through the module");
  record_opt->excludes(demos_opt);
  calibrate_cmd->add_option("--trim", calibrate.trim_fraction,
                            "Share of the experts dropped at each end (0: mean and SD, as the "
                            "MScore; e.g. 0.1: a trimmed mean, as NeuroVR)")
      ->check(CLI::Range(0.0, 0.49));
  calibrate_cmd->add_option("--pass-sds", calibrate.pass_sds,
                            "Pass score = 50 - 10 x this (default 1: one expert SD below the "
                            "experts' mean on average)")
      ->check(CLI::Range(0.0, 5.0));
  calibrate_cmd->add_option("--task-share", calibrate.task_share,
                            "Task rule = this share of the experts' mean of the task metric "
                            "(default 0.25)")
      ->check(CLI::Range(0.0, 1.0));
  calibrate_cmd->add_flag("--leave-one-out", calibrate.leave_one_out,
                          "Also score each expert against the benchmarks of the others");
  calibrate_cmd->add_option("--out", calibrate.out, "Also write the rubric fragment to this file");
  calibrate_cmd->add_flag("--write", calibrate.write,
                          "Put the calibrated rubric into the module file (the rest of the "
                          "file is kept as it is)");
  calibrate_cmd->callback([&] {
    if (calibrate.records.empty() && calibrate.demonstrations.empty()) {
      std::cerr << "acdr calibrate: give --record DB or --demonstrations DIR\n";
      code = 2;
      return;
    }
    code = acdr::run_calibrate(calibrate, std::cout, std::cerr);
  });

  // acdr make-trajectory
  std::string waypoints, trajectory_out;
  double rate_hz = 100.0;
  auto* traj_cmd = app.add_subcommand(
      "make-trajectory", "Sample a smooth (minimum-jerk) trajectory from a waypoint CSV");
  traj_cmd->add_option("waypoints", waypoints, "Waypoint CSV")->required();
  traj_cmd->add_option("output", trajectory_out, "Trajectory CSV to write")->required();
  traj_cmd->add_option("--rate", rate_hz, "Samples per second")->check(CLI::Range(1.0, 10000.0));
  traj_cmd->callback([&] {
    code = acdr::run_make_trajectory(waypoints, trajectory_out, rate_hz, std::cout, std::cerr);
  });

  // Any command that runs out of memory says so and exits as bad input (2), never by a signal.
  const std::string no_memory = acdr::run_catching_allocation_failure([&] {
    try {
      app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
      code = app.exit(e);
    }
  }, "running the command");
  if (!no_memory.empty()) {
    std::cerr << "acdr: " << no_memory << "\n";
    return 2;
  }
  return code;
}
