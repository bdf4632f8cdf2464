// The `acdr` program: parses arguments and calls the libraries. Nothing else lives here.
#include <CLI/CLI.hpp>

#include <iostream>

#include "ui/commands/make_trajectory_command.hpp"
#include "ui/commands/render_command.hpp"
#include "ui/commands/rescore_command.hpp"
#include "ui/commands/run_command.hpp"


int main(int argc, char** argv) {
  CLI::App app{"ACDR Trainer: scooping simulation and assessment for artificial cervical disc "
               "replacement"};
  app.require_subcommand(1);
  app.set_version_flag("--version", ACDR_VERSION_STRING);
  int code = 0;

  // acdr run
  acdr::RunOptions run;
  auto* run_cmd = app.add_subcommand("run", "Run one attempt of a scenario (module)");
  run_cmd->add_option("scenario", run.scenario, "Scenario file (JSON)")->required();
  run_cmd->add_option("--input", run.input, "replay:FILE (a recorded trajectory, CSV)")
      ->required();
  run_cmd->add_option("--trainee", run.trainee, "Trainee id (omit for a practice attempt)");
  run_cmd->add_option("--db", run.db, "Database file (default: $ACDR_DB or the data directory)");
  run_cmd->add_option("--png", run.png, "Write a picture of the final frame");
  run_cmd->add_option("--record", run.record, "Also write the attempt's recording to a file");
  run_cmd->add_flag("--json", run.json, "Print the result as JSON on stdout");
  run_cmd->add_flag("--headless", run.headless, "No window (the only mode in this build)");
  run_cmd->callback([&] { code = acdr::run_run(run, std::cout, std::cerr); });

  // acdr render
  acdr::RenderOptions render;
  auto* render_cmd = app.add_subcommand("render", "Offscreen picture of a scenario's scene");
  render_cmd->add_option("scenario", render.scenario, "Scenario file (JSON)")->required();
  render_cmd->add_option("--png", render.png, "Output PNG")->required();
  render_cmd->add_option("--width", render.width, "Width in pixels");
  render_cmd->add_option("--height", render.height, "Height in pixels");
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

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return code;
}
