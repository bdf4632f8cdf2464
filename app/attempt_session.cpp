// The attempt session: see attempt_session.hpp. Each step below crosses into one library.
#include "app/attempt_session.hpp"

#include <filesystem>
#include <fstream>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "app/allocation_guard.hpp"
#include "app/live_attempt.hpp"
#include "assessment/recording.hpp"
#include "db/attempt_store.hpp"
#include "db/catalog.hpp"
#include "db/checkpoint_writer.hpp"
#include "db/outcome_side_file.hpp"
#include "db/progression.hpp"
#include "scenarios/curriculum_set.hpp"
#include "scenarios/scenario_loader.hpp"

namespace acdr {
namespace {

// How long a headless replay's checkpoint waits for a record another program holds (ms).
constexpr int kHeadlessCheckpointWaitMs = 100;

// Marks the session refused, with why. Returns false (a step that refuses returns it).
bool refuse(SessionResult& result, std::string error, SessionEnd end = SessionEnd::kBadInput) {
  result.end = end;
  result.error = std::move(error);
  return false;
}

// The sink that saves an attempt's checkpoints through `writer` (which must outlive it).
CheckpointSink checkpoint_sink(CheckpointWriter& writer) {
  return [&writer](const CheckpointView& view) {
    return writer.write(view.record, view.first_new_frame, view.first_new_event,
                        view.first_new_bone_sample, view.t_s);
  };
}

// The module (and its curriculum) as the record knows it, updated from the scenario. Returns
// the store's error, or an empty string.
std::string register_one_module(Database& db, const ScenarioModel& scenario) {
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

// The scenario's whole curriculum as the record knows it: every module of the curriculum's
// folder (options.curriculum_dir, or the scenario's own), then the scenario itself, so that
// prerequisites are registered before any has been attempted. Files of the folder that are no
// scenario are noted on `notes`. Returns the store's error, or an empty string.
std::string register_module(Database& db, const ScenarioModel& scenario,
                            const SessionOptions& options, std::ostream& notes) {
  if (!scenario.curriculum.empty()) {
    const std::string dir = !options.curriculum_dir.empty()
                                ? options.curriculum_dir
                                : std::filesystem::path(scenario.path).parent_path().string();
    const CurriculumSet set = load_curriculum_set(dir, scenario.curriculum);
    if (!options.quiet)
      for (const std::string& line : set.skipped) notes << "curriculum: skipped " << line << "\n";
    for (const auto& module : set.modules) {
      if (module->id == scenario.id) continue;  // registered from the file being run, below
      if (std::string e = register_one_module(db, *module); !e.empty()) return e;
    }
  }
  return register_one_module(db, scenario);
}

// The record: opened, the module registered, the progression gate checked, the attempt begun
// (its row exists from the start, status running, so a crash leaves a trace). Sets db_path and
// attempt_id of `result`; nullopt when refused (`result` says why).
std::optional<Database> begin_in_record(const SessionOptions& options,
                                        const ScenarioModel& scenario, SessionResult& result,
                                        std::ostream& notes) {
  result.db_path = options.db.empty() ? default_database_path() : options.db;
  std::vector<std::string> replayed;  // results of earlier attempts kept in side files
  auto db = open_store(result.db_path, {}, &replayed);
  for (const std::string& line : replayed) notes << "note: " << line << "\n";
  if (!db) {
    refuse(result, db.error().message);
    return std::nullopt;
  }
  if (std::string e = register_module(db.value(), scenario, options, notes); !e.empty()) {
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
// empty string. A recording file that cannot be written does not stop the attempt being
// stored: that error goes to `record_file_error`.
std::string store_run(Database& db, std::int64_t attempt_id, const AttemptRun& run,
                      const World& world, const std::string& record_path,
                      double patience_s, const XapiOptions& xapi, std::string* stored_as,
                      std::string* unsaved_file, std::string* record_file_error) {
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
  // As the trainee saw it (below 1: slow motion), or how fast a headless replay ran: the same
  // figure as the result's realtime_factor.
  outcome.realtime_factor = run.wall_s > 0 ? world.time_s() / run.wall_s : -1.0;
  outcome.events = event_records(run.record.events, run.record.summary.zones);
  RecordingData recording;
  recording.format = kRecordingFormat;
  recording.frame_count = static_cast<std::int64_t>(run.record.frames.size());
  recording.bytes = encode_recording(run.record);
  if (!record_path.empty()) {
    std::ofstream file(record_path, std::ios::binary);
    file.write(reinterpret_cast<const char*>(recording.bytes.data()),
               static_cast<std::streamsize>(recording.bytes.size()));
    if (!file) *record_file_error = record_path + ": cannot write the recording";
  }
  outcome.recording = std::move(recording);
  const FinalRecord stored = finish_attempt_or_keep(db, attempt_id, std::move(outcome),
                                                    patience_s, xapi);
  *stored_as = stored.stored ? "completed" : "not written";
  *unsaved_file = stored.side_file;
  return stored.error;
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
    device = open_input(options.input, &error, options.device_timeout_s,
                        scene_instrument_count(scenario.world));
    if (!device) {
      refuse(result, error);
      return result;
    }
  }
  auto* udp = dynamic_cast<UdpDevice*>(device.get());
  // Where statements go and which IRIs they carry: a broken configuration is reported before
  // the attempt rather than after it.
  const LrsConfigLoad lrs = load_lrs_config(options.lrs_config);
  if (!lrs.ok()) {
    refuse(result, lrs.error);
    return result;
  }
  XapiOptions xapi;
  if (!lrs.config.activity_iri_base.empty()) xapi.base_iri = lrs.config.activity_iri_base;

  // The record, then the device's first packet.
  auto db = begin_in_record(options, scenario, result, notes);
  if (!db) return result;
  if (udp && !wait_for_bridge(*udp, options, *db, result, notes)) return result;

  // The attempt. Running out of memory ends it as aborted with a message, never a signal.
  bool view_failed = false;
  const std::string no_memory = run_catching_allocation_failure([&] {
    result.world = std::make_unique<World>(scenario.world);
    if (view || udp) {
      view_failed = !run_live(options, scenario, *result.world, device.get(), view, result, notes, &error);
    } else {
      // A headless replay checkpoints on its stepping thread: while another program holds the
      // record, each checkpoint would stall the attempt for the connection's whole busy timeout.
      // It waits briefly instead; a checkpoint not written goes with the next one, and the final
      // store still waits --store-wait.
      const ScopedBusyTimeout brief(*db, kHeadlessCheckpointWaitMs);
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
  std::string record_file_error;
  const std::string store_error =
      store_run(*db, result.attempt_id, result.run, world, options.record,
                options.store_patience_s, xapi, &result.stored_as, &result.unsaved_file,
                &record_file_error);
  const std::string kept =
      result.unsaved_file.empty()
          ? std::string()
          : "; the result is kept in " + result.unsaved_file +
                " and will be stored at the next start of acdr on this record";
  if (view && result.run.end != AttemptEnd::kStopped)
    view->show_score(result.run,
                     store_error.empty()
                         ? "Stored as attempt " + std::to_string(result.attempt_id) + " (" +
                               result.stored_as + ")"
                         : "Could not store the attempt: " + store_error + kept);
  if (!store_error.empty()) {
    // The attempt ran: its result is shown, and the exit says the record is not written.
    refuse(result, "the record of attempt " + std::to_string(result.attempt_id) +
                       " could not be written: " + store_error + kept,
           SessionEnd::kRecordNotWritten);
    return result;
  }
  if (!record_file_error.empty()) {
    // The training record has the attempt and its recording; only the extra file is missing.
    refuse(result, record_file_error + " (attempt " + std::to_string(result.attempt_id) +
                       " is stored, " + result.stored_as + ", with its recording)",
           SessionEnd::kRecordNotWritten);
    return result;
  }
  result.end = result.run.end == AttemptEnd::kNumericalFailure ? SessionEnd::kNumericalFailure
               : result.run.end == AttemptEnd::kStopped        ? SessionEnd::kAbandoned
                                                                : SessionEnd::kCompleted;
  // Stored first; now, when asked, one pass over the outbox without waiting for an
  // unreachable store (what does not go now waits for `acdr send` or the next attempt).
  if (lrs.config.send_after_attempt) {
    DeliveryOptions once;
    once.retry_for_s = 0.0;
    result.delivery = deliver_outbox(*db, lrs.config, once);
  }
  return result;
}

}  // namespace acdr
