// `acdr run`: load the scenario, open the input and the record, run the attempt, store it with
// its recording in one transaction, draw the last frame, report.
#include "ui/commands/run_command.hpp"

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <ostream>

#include "assessment/recording.hpp"
#include "db/attempt_store.hpp"
#include "db/catalog.hpp"
#include "db/progression.hpp"
#include "scenarios/scenario_loader.hpp"
#include "ui/attempt_runner.hpp"
#include "ui/offscreen_render.hpp"
#include "ui/result_format.hpp"
#include "ui/scene_snapshot.hpp"

namespace acdr {

int run_run(const RunOptions& options, std::ostream& out, std::ostream& err) {
  // Scenario and input first: bad files are reported before anything is stored.
  const LoadResult loaded = load_scenario_file(options.scenario);
  if (!loaded.ok()) {
    err << to_string(loaded.errors);
    return 2;
  }
  const ScenarioModel& scenario = *loaded.model;
  std::string error;
  auto device = open_input(options.input, &error);
  if (!device) {
    err << error << "\n";
    return 2;
  }

  // The attempt row exists from the start (status running) so a crash leaves a trace.
  const std::string db_path = options.db.empty() ? default_database_path() : options.db;
  auto db = open_store(db_path);
  if (!db) {
    err << db.error().message << "\n";
    return 2;
  }
  if (!scenario.curriculum.empty()) {
    if (auto c = upsert_curriculum(db.value(), CurriculumRecord{scenario.curriculum,
                                                                scenario.curriculum});
        !c) {
      err << c.error().message << "\n";
      return 2;
    }
  }
  ModuleRecord module;
  module.id = scenario.id;
  if (!scenario.curriculum.empty()) module.curriculum_id = scenario.curriculum;
  module.position = scenario.module_order;
  module.title = scenario.title;
  module.scenario_path = scenario.path;
  module.scenario_hash = scenario.hash;
  module.pass_score = scenario.rubric.pass_score;
  module.consecutive_passes_required = scenario.rubric.consecutive_passes_to_master;
  if (auto registered = upsert_module(db.value(), module); !registered) {
    err << registered.error().message << "\n";
    return 2;
  }
  // Proficiency-based progression: a trainee may take a module once its prerequisites are
  // mastered, unless an instructor overrides (recorded with the attempt). Practice attempts
  // (no trainee) are never locked.
  if (options.override_lock && options.override_by.empty()) {
    err << "--override needs --override-by NAME (who decided)\n";
    return 2;
  }
  if (options.trainee && !options.override_lock) {
    auto decision = check_unlocked(db.value(), *options.trainee, scenario.id);
    if (!decision) {
      err << decision.error().message << "\n";
      return 2;
    }
    if (!decision.value().unlocked) {
      err << "module '" << scenario.id << "' is locked for trainee '" << *options.trainee
          << "': " << decision.value().reason
          << " (an instructor may allow it with --override --override-by NAME)\n";
      return 3;
    }
  }
  AttemptStart start;
  start.override_lock = options.override_lock;
  start.override_by = options.override_by;
  start.override_reason = options.override_reason;
  start.trainee_id = options.trainee;
  start.module_id = scenario.id;
  start.input_device = options.input;
  start.program_version = ACDR_VERSION_STRING;
  start.scenario_hash = scenario.hash;
  auto attempt_id = begin_attempt(db.value(), start);
  if (!attempt_id) {
    err << attempt_id.error().message << "\n";
    return 2;
  }

  World world(scenario.world);
  AttemptRun run = run_attempt(scenario, world, *device);

  // Store everything in one transaction.
  AttemptOutcome outcome;
  outcome.metrics = run.metrics;
  outcome.score = run.score;
  outcome.duration_s = world.time_s();
  for (const Event& e : run.record.events)
    outcome.events.push_back(EventRecord{e.t_s, event_kind_name(e.kind), "", e.value, e.detail});
  RecordingData recording;
  recording.format = kRecordingFormat;
  recording.frame_count = static_cast<std::int64_t>(run.record.frames.size());
  recording.bytes = encode_recording(run.record);
  if (!options.record.empty()) {
    std::ofstream file(options.record, std::ios::binary);
    file.write(reinterpret_cast<const char*>(recording.bytes.data()),
               static_cast<std::streamsize>(recording.bytes.size()));
    if (!file) {
      err << options.record << ": cannot write the recording\n";
      return 2;
    }
  }
  outcome.recording = std::move(recording);
  if (auto stored = finish_attempt(db.value(), attempt_id.value(), outcome); !stored) {
    err << stored.error().message << "\n";
    return 2;
  }

  // Picture of the final frame.
  if (!options.png.empty()) {
    const RenderScene scene = snapshot_world(
        world, static_cast<float>(options.png_width) / static_cast<float>(options.png_height));
    if (!render_to_png(scene, options.png_width, options.png_height, options.png, &error)) {
      err << options.png << ": " << error << "\n";
      return 2;
    }
  }

  ResultContext context{scenario, run, world, attempt_id.value(), db_path, options.png};
  if (options.json)
    out << result_json(context).dump(2) << "\n";
  else
    out << result_summary(context);
  return run.end == AttemptEnd::kNumericalFailure ? 1 : 0;
}

}  // namespace acdr
