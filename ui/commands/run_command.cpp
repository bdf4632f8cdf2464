// `acdr run`: load the scenario, open the input and the record, run the attempt (in the trainee
// view's window, live on the haptic thread for a bridge, or as fast as possible for a replay),
// store it with its recording in one transaction, draw the last frame, report.
#include "ui/commands/run_command.hpp"

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>

#include "app/attempt_runner.hpp"
#include "app/live_attempt.hpp"
#include "assessment/recording.hpp"
#include "db/attempt_store.hpp"
#include "db/catalog.hpp"
#include "db/checkpoint_writer.hpp"
#include "db/progression.hpp"
#include "engine/devices/udp_device.hpp"
#include "scenarios/scenario_loader.hpp"
#include "ui/offscreen_render.hpp"
#include "ui/result_format.hpp"
#include "ui/scene_snapshot.hpp"
#include "ui/trainee_view.hpp"

namespace acdr {
namespace {

// The sink that saves an attempt's checkpoints through `writer` (which must outlive it).
CheckpointSink checkpoint_sink(CheckpointWriter& writer) {
  return [&writer](const CheckpointView& view) {
    return writer.write(view.record, view.first_new_frame, view.first_new_event, view.t_s);
  };
}

// Stores the run: finished in one transaction, or aborted when the trainee abandoned it.
// Returns false with `error` set when the store refused.
bool store_run(Database& db, std::int64_t attempt_id, const AttemptRun& run, const World& world,
               const RunOptions& options, std::string* stored_as, std::string* error) {
  if (run.end == AttemptEnd::kStopped) {
    *stored_as = "aborted";
    if (auto aborted = abort_attempt(db, attempt_id, "stopped before the end by the trainee");
        !aborted) {
      *error = aborted.error().message;
      return false;
    }
    return true;
  }
  AttemptOutcome outcome;
  outcome.metrics = run.metrics;
  outcome.score = run.score;
  outcome.duration_s = world.time_s();
  outcome.events = event_records(run.record.events, run.record.summary.zones);
  RecordingData recording;
  recording.format = kRecordingFormat;
  recording.frame_count = static_cast<std::int64_t>(run.record.frames.size());
  recording.bytes = encode_recording(run.record);
  if (!options.record.empty()) {
    std::ofstream file(options.record, std::ios::binary);
    file.write(reinterpret_cast<const char*>(recording.bytes.data()),
               static_cast<std::streamsize>(recording.bytes.size()));
    if (!file) {
      *error = options.record + ": cannot write the recording";
      return false;
    }
  }
  outcome.recording = std::move(recording);
  *stored_as = "completed";
  if (auto stored = finish_attempt(db, attempt_id, outcome); !stored) {
    *error = stored.error().message;
    return false;
  }
  return true;
}

}  // namespace

int run_run(const RunOptions& options, std::ostream& out, std::ostream& err) {
  // Scenario and input first: bad files are reported before anything is stored.
  const LoadResult loaded = load_scenario_file(options.scenario);
  if (!loaded.ok()) {
    err << to_string(loaded.errors);
    return 2;
  }
  const ScenarioModel& scenario = *loaded.model;
  const bool mouse = options.input == "mouse";
  bool windowed = !options.headless;
  if (windowed && !display_available()) {
    if (mouse) {
      err << "--input mouse needs a window, and there is no display (DISPLAY is not set)\n";
      return 2;
    }
    err << "note: no display, running headless\n";
    windowed = false;
  }
  std::string error;
  std::unique_ptr<InputDevice> device;
  if (!mouse) {
    if (options.input.rfind("udp:", 0) == 0) {
      // The bridge's port, with the documented timeouts.
      UdpDeviceOptions udp;
      char* end = nullptr;
      const long port = std::strtol(options.input.c_str() + 4, &end, 10);
      if (*end != '\0' || port < 1 || port > 65535) {
        err << "--input udp:PORT needs a port number 1-65535 (got '" << options.input << "')\n";
        return 2;
      }
      udp.port = static_cast<int>(port);
      udp.disconnect_timeout_s = options.device_timeout_s;
      device = UdpDevice::open(udp, &error);
    } else {
      device = open_input(options.input, &error);
    }
    if (!device) {
      err << error << "\n";
      return 2;
    }
  }
  auto* udp = dynamic_cast<UdpDevice*>(device.get());

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
      // The reason already names the module, the trainee and what is missing.
      err << decision.value().reason << " with --override --override-by NAME\n";
      return 4;
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

  // A bridge-driven attempt starts with the bridge's first packet.
  if (udp) {
    if (!options.json)
      err << "waiting for the device bridge on udp:" << udp->port() << " (up to "
          << options.device_timeout_s << " s)\n";
    if (!udp->wait_for_connection(options.device_timeout_s)) {
      const std::string reason = "no packet from the device bridge on udp:" +
                                 std::to_string(udp->port()) + " within " +
                                 std::to_string(options.device_timeout_s) + " s";
      (void)abort_attempt(db.value(), attempt_id.value(), reason);
      err << reason << " (attempt " << attempt_id.value() << " stored as aborted)\n";
      return 2;
    }
  }

  World world(scenario.world);
  AttemptRun run;
  HapticsReport haptics;
  bool live = false;
  std::string stored_as;
  bool stored = false;

  // A live attempt (window, bridge) writes its checkpoints on a thread of its own
  // (app/live_attempt_checkpoints.hpp), through a connection of its own (one per thread,
  // db/database.hpp); the main connection is not used until that thread has ended, when the
  // attempt is stored.
  const bool live_run = windowed || udp != nullptr;
  std::optional<Database> checkpoint_db;
  std::optional<CheckpointWriter> live_writer;
  CheckpointSink live_sink;
  if (live_run && options.checkpoint_every_s > 0) {
    OpenOptions open;
    open.create = false;
    if (auto second = Database::open(db_path, open); second) {
      checkpoint_db.emplace(std::move(second.value()));
      live_writer.emplace(*checkpoint_db, attempt_id.value(), err);
      live_sink = checkpoint_sink(*live_writer);
    } else {
      err << "warning: the attempt runs without checkpoints: " << second.error().message << "\n";
    }
  }
  LiveCheckpointStats checkpoint_stats;

  if (windowed) {
    TraineeViewOptions view;
    view.screenshot = options.screenshot;
    view.screenshot_at_s = options.screenshot_at_s;
    view.score_screenshot = options.score_screenshot;
    view.close_after_s = options.close_after_s;
    view.input_label = options.input;
    view.loop.realtime_priority = options.realtime;
    view.checkpoint_every_s = options.checkpoint_every_s;
    view.checkpoint_sink = live_sink;
    std::string store_error;
    TraineeViewOutcome outcome = run_trainee_view(
        scenario, world, device.get(), view, [&](const AttemptRun& finished) -> std::string {
          stored = store_run(db.value(), attempt_id.value(), finished, world, options,
                             &stored_as, &store_error);
          if (!stored) return "Could not store the attempt: " + store_error;
          return "Stored as attempt " + std::to_string(attempt_id.value()) + " (" + stored_as +
                 ")";
        });
    if (!outcome.ok) {
      (void)abort_attempt(db.value(), attempt_id.value(), "window failed: " + outcome.error);
      err << "cannot open the trainee view: " << outcome.error << "\n";
      return 2;
    }
    if (!stored) {
      err << store_error << "\n";
      return 2;
    }
    run = std::move(outcome.run);
    haptics.loop = outcome.haptics;
    checkpoint_stats = outcome.checkpoints;
    live = true;
  } else {
    if (udp) {
      // A live device: its own 1 kHz loop, the physics at the scenario's rate, both paced.
      HapticLoopOptions loop;
      loop.realtime_priority = options.realtime;
      LiveAttempt attempt(scenario, world, *device, loop);
      attempt.set_checkpoints(options.checkpoint_every_s, live_sink);
      attempt.start();
      run = attempt.wait();
      checkpoint_stats = attempt.checkpoint_stats();
      haptics.loop = attempt.haptic_stats();
      haptics.decoupled = attempt.decoupled();
      haptics.physics = attempt.physics_stats();
      haptics.device_ticks_clamped = attempt.device_clamped_ticks();
      haptics.device_ticks_zeroed = attempt.device_zeroed_ticks();
      live = true;
    } else {
      CheckpointWriter checkpoints(db.value(), attempt_id.value(), err);
      run = run_attempt(scenario, world, *device, {}, options.checkpoint_every_s,
                        checkpoint_sink(checkpoints));
    }
    std::string store_error;
    if (!store_run(db.value(), attempt_id.value(), run, world, options, &stored_as,
                   &store_error)) {
      err << store_error << "\n";
      return 2;
    }
  }
  if (udp) {
    haptics.has_link = true;
    haptics.link = udp->stats();
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
  context.haptics = live ? &haptics : nullptr;
  context.stored_as = stored_as;
  if (options.json) {
    nlohmann::json result = result_json(context);
    if (live_writer) {
      // What the checkpoints cost: on the writer thread per checkpoint, and on the physics
      // thread per hand-over (haptics.physics has the physics loop's step times).
      const LiveCheckpointStats& c = checkpoint_stats;
      result["checkpoints"] = {{"every_s", options.checkpoint_every_s},
                               {"saved", c.saved},
                               {"failed", c.failed},
                               {"deferred", c.deferred},
                               {"frames_saved", c.frames_saved},
                               {"largest_frames", c.largest_frames},
                               {"write_mean_ms", c.write_mean_ms},
                               {"write_max_ms", c.write_max_ms},
                               {"handover_max_ms", c.handover_max_ms},
                               {"writer_background_priority", c.background_priority}};
    }
    out << result.dump(2) << "\n";
  } else {
    out << result_summary(context);
    if (live_writer) {
      const LiveCheckpointStats& c = checkpoint_stats;
      char line[200];
      std::snprintf(line, sizeof line,
                    "  checkpoints            %lld saved every %g s (writer thread: mean %.1f "
                    "ms, max %.1f ms; %lld deferred)\n",
                    static_cast<long long>(c.saved), options.checkpoint_every_s,
                    c.write_mean_ms, c.write_max_ms, static_cast<long long>(c.deferred));
      out << line;
    }
  }
  if (run.end == AttemptEnd::kNumericalFailure) return 1;
  if (run.end == AttemptEnd::kStopped) return 3;
  return 0;
}

}  // namespace acdr
