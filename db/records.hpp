// Plain data of the training record, as stores return them and callers fill them: trainees,
// curricula, modules, attempts with their events and recordings. No SQL here.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "assessment/attempt_result.hpp"

namespace acdr {

struct TraineeRecord {
  std::string id;            ///< opaque, chosen by the institution (e.g. "t-0042")
  std::string display_name;  ///< optional, shown in the dashboard
  std::string created_utc;   ///< set by the store on first insert
};

struct CurriculumRecord {
  std::string id;
  std::string title;
};

/// A graded module: one scenario file with its proficiency rule.
struct ModuleRecord {
  std::string id;                            ///< stable module id, e.g. "box-warmup"
  std::optional<std::string> curriculum_id;  ///< nullopt: a stand-alone module
  int position = 0;                          ///< order within the curriculum
  std::string title;
  std::string scenario_path;
  std::string scenario_hash;  ///< FNV-1a 64 of the scenario file, hex
  /// Set by the store: 1 on first registration, +1 whenever the scenario hash changes.
  int version = 1;
  /// nullopt: the prerequisites are the module(s) immediately before this one in its
  /// curriculum (none for the first or a stand-alone module). A vector (maybe empty): exactly
  /// these module ids.
  std::optional<std::vector<std::string>> prerequisites;
  /// Passing attempts in a row needed to master the module (FLS / MScore: 2).
  int consecutive_passes_required = 2;
  double pass_score = 50.0;  ///< composite score (0..100) an attempt needs to pass
};

enum class AttemptStatus { kRunning, kCompleted, kAborted };

/// "running", "completed", "aborted".
const char* attempt_status_name(AttemptStatus status);
std::optional<AttemptStatus> parse_attempt_status(std::string_view text);

/// One timed event of an attempt, as stored. `kind` is a stable name ("zone_warning",
/// "overload_yield", "numerical", ...) rather than an enum value, so old records stay readable
/// when the engine's enum changes.
struct EventRecord {
  double t_s = 0.0;    ///< simulated time since the attempt started (s)
  std::string kind;
  std::string zone;    ///< danger zone name; empty (stored NULL) when not about a zone
  double value = 0.0;  ///< kind-specific: force (N), moment (N·m), distance (m), ...
  std::string detail;  ///< free text (e.g. the solver stage that produced a NaN)
  /// The zone's index in the recording's zone list (WorldSummary::zones); -1 (stored NULL)
  /// when not about a zone or unknown.
  std::int32_t zone_index = -1;
};

/// The recorded input and frame stream of an attempt. The byte layout is named by `format` and
/// owned by its writer; the store compresses it and never looks inside.
struct RecordingData {
  std::string format;  ///< e.g. "acdr-frames-v1"
  std::int64_t frame_count = 0;
  std::vector<std::uint8_t> bytes;  ///< uncompressed
  bool complete = true;             ///< false for a checkpoint of an unfinished attempt
};

/// What a running attempt appends at a checkpoint (append_checkpoint): only what is new since
/// the previous checkpoint, so each costs about the new data, not the whole attempt so far.
struct AttemptCheckpoint {
  std::vector<EventRecord> new_events;  ///< events since the previous checkpoint, in time order
  /// The next piece of the recording's byte stream (format, frames in it, bytes). Pieces are
  /// stored (and compressed) one by one and read back concatenated in order.
  std::optional<RecordingData> chunk;
  /// Metrics of the recording so far; replace the stored ones (an aborted attempt keeps them).
  std::optional<Metrics> metrics;
  double duration_s = -1.0;  ///< simulated time so far (s); < 0: leave the stored value
};

/// What begin_attempt needs to know when an attempt starts.
struct AttemptStart {
  std::optional<std::string> trainee_id;  ///< nullopt: a practice attempt
  std::string module_id;                  ///< must be registered (catalog.hpp: upsert_module)
  std::string input_device;               ///< "replay:demo.csv", "mouse", "udp:7000", ...
  std::string program_version;
  std::string scenario_hash;
  bool override_lock = false;    ///< an instructor let the trainee take a locked module
  std::string override_by;       ///< who decided (required when override_lock)
  std::string override_reason;
  std::string started_utc;       ///< empty: now
};

/// What finish_attempt stores when an attempt ends normally.
struct AttemptOutcome {
  Metrics metrics;
  ScoreResult score;
  std::vector<EventRecord> events;          ///< all events of the attempt, in time order
  std::optional<RecordingData> recording;   ///< the whole stream
  double duration_s = -1.0;                 ///< simulated duration (s); < 0: unknown
  /// Simulated seconds per wall-clock second over the attempt (below 1: slow motion, as the
  /// trainee saw it; a headless replay's own speed); <= 0 or not finite: unknown (stored NULL).
  double realtime_factor = -1.0;
  std::string ended_utc;                    ///< empty: now
};

/// A stored attempt. `events` and `recording` are filled only when asked for.
struct AttemptRecord {
  std::int64_t id = 0;
  std::string uuid;          ///< globally unique attempt id (also the xAPI session id)
  std::string registration;  ///< xAPI/cmi5 registration UUID
  std::optional<std::string> trainee_id;  ///< nullopt: practice
  std::string module_id;
  AttemptStatus status = AttemptStatus::kRunning;
  std::string started_utc;
  std::optional<std::string> ended_utc;
  std::string heartbeat_utc;  ///< last sign of life of the writer (begin or checkpoint)
  std::optional<double> duration_s;
  /// Simulated seconds per wall-clock second over the attempt; nullopt: not known (attempts
  /// stored before the record kept it, aborted attempts).
  std::optional<double> realtime_factor;
  std::string input_device;
  std::string program_version;
  std::string scenario_hash;
  bool override_lock = false;
  std::string override_by;
  std::string override_reason;
  std::optional<double> score;  ///< composite 0..100, set when completed
  std::optional<bool> passed;   ///< set when completed
  std::string abort_reason;
  std::int64_t writer_pid = 0;
  std::string writer_host;

  Metrics metrics;
  ScoreResult score_detail;  ///< terms, gates and reasons (score/passed mirror the above)
  std::vector<EventRecord> events;
  std::optional<RecordingData> recording;

  bool is_practice() const { return !trainee_id.has_value(); }
};

}  // namespace acdr
