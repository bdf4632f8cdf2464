// The attempt session: see attempt_session.hpp. Each step below crosses into one library.
#include "app/attempt_session.hpp"

#include <fstream>
#include <optional>
#include <ostream>

#include "app/allocation_guard.hpp"
#include "app/live_attempt.hpp"
#include "assessment/recording.hpp"
#include "db/attempt_store.hpp"
#include "db/catalog.hpp"
#include "db/checkpoint_writer.hpp"
#include "db/progression.hpp"
#include "scenarios/scenario_loader.hpp"

namespace acdr {
namespace {

// Marks the session refused, with why. Returns false (a step that refuses returns it).
bool refuse(SessionResult& result, std::string error, SessionEnd end = SessionEnd::kBadInput) {
  result.end = end;
  result.error = std::move(error);
  return false;
}

// The sink that saves an attempt's checkpoints through `writer` (which must outlive it).
CheckpointSink checkpoint_sink(CheckpointWriter& writer) {
  return [&writer](const CheckpointView& view) {
    return writer.write(view.record, view.first_new_frame, view.first_new_event, view.t_s);
  };
}

// The module (and its curriculum) as the record knows it, updated from the scenario. Returns
// the store's error, or an empty string.
std::string register_module(Database& db, const ScenarioModel& scenario) {
  if (!scenario.curriculum.empty()) {
    if (auto c = upsert_curriculum(db, CurriculumRecord{scenario.curriculum, scenario.curriculum});
        !c)
      return c.error().message;
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
  if (auto registered = upsert_module(db, module); !registered) return registered.error().message;
  return {};
}

// The record: opened, the module registered, the progression gate checked, the attempt begun
// (its row exists from the start, status running, so a crash leaves a trace). Sets db_path and
// attempt_id of `result`; nullopt when refused (`result` says why).
std::optional<Database> begin_in_record(const SessionOptions& options,
                                        const ScenarioModel& scenario, SessionResult& result) {
  result.db_path = options.db.empty() ? default_database_path() : options.db;
  auto db = open_store(result.db_path);
  if (!db) {
    refuse(result, db.error().message);
    return std::nullopt;
  }
  if (std::string e = register_module(db.value(), scenario); !e.empty()) {
    refuse(result, e);
    return std::nullopt;
  }
  // Proficiency-based progression: a trainee may take a module once its prerequisites are
  // mastered, unless an instructor overrides (recorded with the attempt). Practice attempts
  // (no trainee) are never locked.
  if (options.override_lock && options.override_by.empty()) {
    refuse(result, "--override needs --override-by NAME (who decided)");
    return std::nullopt;
  }
  if (options.trainee && !options.override_lock) {
    auto decision = check_unlocked(db.value(), *options.trainee, scenario.id);
    if (!decision) {
      refuse(result, decision.error().message);
      return std::nullopt;
    }
    // The reason already names the module, the trainee and what is missing.
    if (!decision.value().unlocked) {
      refuse(result, decision.value().reason + " with --override --override-by NAME",
             SessionEnd::kLocked);
      return std::nullopt;
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
    refuse(result, attempt_id.error().message);
    return std::nullopt;
  }
  result.attempt_id = attempt_id.value();
  return std::move(db.value());
}

// A bridge-driven attempt starts with the bridge's first packet; without one in time the
// attempt is stored as aborted. Returns false when refused (`result` says why).
bool wait_for_bridge(UdpDevice& udp, const SessionOptions& options, Database& db,
                     SessionResult& result, std::ostream& notes) {
  if (!options.quiet)
    notes << "waiting for the device bridge on udp:" << udp.port() << " (up to "
          << options.device_timeout_s << " s)\n";
  if (udp.wait_for_connection(options.device_timeout_s)) return true;
  const std::string reason = "no packet from the device bridge on udp:" +
                             std::to_string(udp.port()) + " within " +
                             std::to_string(options.device_timeout_s) + " s";
  (void)abort_attempt(db, result.attempt_id, reason);
  return refuse(result, reason + " (attempt " + std::to_string(result.attempt_id) +
                            " stored as aborted)");
}

// Stores the run: finished in one transaction (with the recording, also written to
// `record_path` when set), or aborted when the trainee abandoned it. Returns the error, or an
// empty string.
std::string store_run(Database& db, std::int64_t attempt_id, const AttemptRun& run,
                      const World& world, const std::string& record_path,
                      std::string* stored_as) {
  if (run.end == AttemptEnd::kStopped) {
    *stored_as = "aborted";
    if (auto aborted = abort_attempt(db, attempt_id, "stopped before the end by the trainee");
        !aborted)
      return aborted.error().message;
    return {};
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
  if (!record_path.empty()) {
    std::ofstream file(record_path, std::ios::binary);
    file.write(reinterpret_cast<const char*>(recording.bytes.data()),
               static_cast<std::streamsize>(recording.bytes.size()));
    if (!file) return record_path + ": cannot write the recording";
  }
  outcome.recording = std::move(recording);
  *stored_as = "completed";
  if (auto stored = finish_attempt(db, attempt_id, outcome); !stored)
    return stored.error().message;
  return {};
}

// A live attempt (window, bridge), paced on the haptic thread and watched by `view` when there
// is one. Its checkpoints go through a writer thread of its own with a connection of its own
// (one per thread, db/database.hpp); the main connection is not used until that thread has
// ended. Returns false with `error` set when the view cannot be opened.
bool run_live(const SessionOptions& options, const ScenarioModel& scenario, World& world,
              InputDevice* device, AttemptView* view, SessionResult& result, std::ostream& notes,
              std::string* error) {
  std::optional<Database> checkpoint_db;
  std::optional<CheckpointWriter> writer;
  CheckpointSink sink;
  if (options.checkpoint_every_s > 0) {
    OpenOptions open;
    open.create = false;
    if (auto second = Database::open(result.db_path, open); second) {
      checkpoint_db.emplace(std::move(second.value()));
      writer.emplace(*checkpoint_db, result.attempt_id, notes);
      sink = checkpoint_sink(*writer);
    } else {
      notes << "warning: the attempt runs without checkpoints: " << second.error().message
            << "\n";
    }
  }
  if (view && !view->open(scenario, world, device, error)) return false;
  // A live device: its own 1 kHz loop, the physics at the scenario's rate, both paced.
  HapticLoopOptions loop;
  loop.realtime_priority = options.realtime;
  LiveAttempt live(scenario, world, view ? view->device() : *device, loop);
  live.set_checkpoints(options.checkpoint_every_s, sink);
  live.start();
  if (view) view->watch(live);
  result.run = live.wait();
  HapticsReport& haptics = result.haptics.emplace();
  haptics.loop = live.haptic_stats();
  haptics.decoupled = live.decoupled();
  haptics.physics = live.physics_stats();
  haptics.device_ticks_clamped = live.device_clamped_ticks();
  haptics.device_ticks_zeroed = live.device_zeroed_ticks();
  if (auto* udp = dynamic_cast<UdpDevice*>(device)) {
    haptics.has_link = true;
    haptics.link = udp->stats();
  }
  if (writer) result.checkpoints = CheckpointReport{options.checkpoint_every_s,
                                                    live.checkpoint_stats()};
  return true;
}

}  // namespace

SessionResult run_attempt_session(const SessionOptions& options, AttemptView* view,
                                  std::ostream& notes) {
  SessionResult result;
  // Scenario and input first: bad files are reported before anything is stored.
  const LoadResult loaded = load_scenario_file(options.scenario);
  if (!loaded.ok()) {
    std::string errors = to_string(loaded.errors);
    if (!errors.empty() && errors.back() == '\n') errors.pop_back();
    refuse(result, errors);
    return result;
  }
  result.scenario = loaded.model;
  const ScenarioModel& scenario = *result.scenario;
  const bool mouse = options.input == "mouse";
  if (view && !view->can_open()) {
    if (mouse) {
      refuse(result, "--input mouse needs a window, and there is no display (DISPLAY is not set)");
      return result;
    }
    notes << "note: no display, running headless\n";
    view = nullptr;
  }
  std::string error;
  std::unique_ptr<InputDevice> device;
  if (!(mouse && view)) {
    device = open_input(options.input, &error, options.device_timeout_s);
    if (!device) {
      refuse(result, error);
      return result;
    }
  }
  auto* udp = dynamic_cast<UdpDevice*>(device.get());

  // The record, then the device's first packet.
  auto db = begin_in_record(options, scenario, result);
  if (!db) return result;
  if (udp && !wait_for_bridge(*udp, options, *db, result, notes)) return result;

  // The attempt. Running out of memory ends it as aborted with a message, never a signal.
  bool view_failed = false;
  const std::string no_memory = run_catching_allocation_failure([&] {
    result.world = std::make_unique<World>(scenario.world);
    if (view || udp) {
      view_failed = !run_live(options, scenario, *result.world, device.get(), view, result, notes, &error);
    } else {
      CheckpointWriter checkpoints(*db, result.attempt_id, notes);
      result.run = run_attempt(scenario, *result.world, *device, {}, options.checkpoint_every_s,
                               checkpoint_sink(checkpoints));
    }
  }, "building or running the scene");
  if (!no_memory.empty()) {
    result.world.reset();
    (void)abort_attempt(*db, result.attempt_id, no_memory);
    refuse(result, no_memory + " (attempt " + std::to_string(result.attempt_id) + " stored as aborted)");
    return result;
  }
  World& world = *result.world;
  if (view_failed) {
    (void)abort_attempt(*db, result.attempt_id, "window failed: " + error);
    refuse(result, "cannot open the trainee view: " + error);
    return result;
  }

  // The record again: stored before the score shows, so closing the score screen loses nothing.
  const std::string store_error = store_run(*db, result.attempt_id, result.run, world,
                                            options.record, &result.stored_as);
  if (view && result.run.end != AttemptEnd::kStopped)
    view->show_score(result.run,
                     store_error.empty()
                         ? "Stored as attempt " + std::to_string(result.attempt_id) + " (" +
                               result.stored_as + ")"
                         : "Could not store the attempt: " + store_error);
  if (!store_error.empty()) {
    refuse(result, store_error);
    return result;
  }
  result.end = result.run.end == AttemptEnd::kNumericalFailure ? SessionEnd::kNumericalFailure
               : result.run.end == AttemptEnd::kStopped        ? SessionEnd::kAbandoned
                                                                : SessionEnd::kCompleted;
  return result;
}

}  // namespace acdr
