// The life of an attempt in the record: begun (`running`, committed at once, before the first
// device packet), optionally checkpointed, then finished in one transaction (`completed`) — or
// found `aborted` when its process is gone. Also reading attempts back.
//
// The abort rule (mark_interrupted_attempts): a `running` attempt is aborted when the process
// that began it can no longer be writing, judged by writer_identity.hpp: the pid is gone, is a
// zombie, now belongs to a process started at another time, or the attempt was begun on
// another host or before a reboot. A process never aborts its own running attempts. The
// aborted attempt keeps what was committed: its start row and the last checkpoint's events and
// recording; the uncommitted tail of a killed transaction is discarded by SQLite (WAL).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "db/database.hpp"
#include "db/records.hpp"
#include "db/xapi.hpp"

namespace acdr {

/// Opens the record for use by a program: Database::open; then (unless read-only) stores the
/// outcomes of finished attempts that could not be written when they ended
/// (outcome_side_file.hpp: their side files), and mark_interrupted_attempts, so an attempt
/// left `running` by a killed run shows as `aborted` from here on (one whose side file is
/// still waiting is left running). `notes`, when given, receives one line per side file.
DbResult<Database> open_store(const std::string& path, const OpenOptions& options = {},
                              std::vector<std::string>* notes = nullptr);

/// Inserts the attempt as `running` and commits at once; returns its id. A trainee id that is
/// not registered yet is registered (empty display name). The module must be registered. The
/// registration UUID is the trainee's existing one for this module, else a new one; a practice
/// attempt always gets its own. Records this process as the writer.
DbResult<std::int64_t> begin_attempt(Database& db, const AttemptStart& start);

/// Saves the events and recording so far of a running attempt (each call replaces the previous
/// checkpoint; `recording` is stored with complete = false) and refreshes its heartbeat, in one
/// transaction. Costs about the size of what is passed: call every few seconds, not per frame.
DbStatus checkpoint_attempt(Database& db, std::int64_t attempt_id,
                            const std::vector<EventRecord>& events,
                            const RecordingData* recording);

/// Appends a checkpoint to a running attempt, in one short transaction: the new events
/// (numbered on after the stored ones), the next recording piece (compressed on its own, stored
/// in recording_chunks), the metrics so far (replacing the stored ones), the simulated
/// duration so far and a fresh heartbeat. If the process is then killed, the attempt is later
/// aborted with exactly this: load_attempt returns the pieces concatenated (complete = false).
/// Use either this or checkpoint_attempt for one attempt, not both (a checkpoint_attempt
/// recording hides the pieces).
DbStatus append_checkpoint(Database& db, std::int64_t attempt_id,
                           const AttemptCheckpoint& checkpoint);

/// Stores metrics, score (with terms, gates, reasons), all events and the recording, sets the
/// end time and status `completed` — all in ONE transaction: after a crash the attempt is either
/// completed with everything or still as before. Only a `running` attempt can be finished.
/// A recording given here replaces any checkpointed pieces. A trainee attempt's xAPI
/// statements (IRIs from `xapi`) are queued in the outbox in the same transaction
/// (outbox.hpp): store first, send after.
DbStatus finish_attempt(Database& db, std::int64_t attempt_id, const AttemptOutcome& outcome,
                        const XapiOptions& xapi = {});

/// finish_attempt, waiting for another connection's lock and trying again while the database
/// is busy or locked (or full: space may come back) for up to `patience_s` in all. Other
/// errors are returned at once.
DbStatus finish_attempt_patiently(Database& db, std::int64_t attempt_id,
                                  const AttemptOutcome& outcome, double patience_s,
                                  const XapiOptions& xapi = {});

/// Ends a running attempt as `aborted` on purpose (the trainee quit), keeping what was
/// checkpointed; `reason` is stored.
DbStatus abort_attempt(Database& db, std::int64_t attempt_id, const std::string& reason);

/// Applies the abort rule above to every `running` attempt except those in `spared` (attempts
/// whose outcome waits in a side file); returns the ids it aborted.
DbResult<std::vector<std::int64_t>> mark_interrupted_attempts(
    Database& db, const std::vector<std::int64_t>& spared = {});

/// Replaces the metrics and score of a completed attempt (re-scoring with a newer rubric), in
/// one transaction. Status, times, events and recording are kept.
DbStatus update_attempt_assessment(Database& db, std::int64_t attempt_id, const Metrics& metrics,
                                   const ScoreResult& score);

/// Replaces the metrics of an aborted attempt (re-computed from its checkpointed recording), in
/// one transaction. It stays aborted, without a score and not passed: an attempt that did not
/// end is never judged, and never counts toward progression. Only an `aborted` attempt.
DbStatus update_aborted_metrics(Database& db, std::int64_t attempt_id, const Metrics& metrics);

/// What load_attempt and list_attempts read besides the attempt row.
struct AttemptDetail {
  bool metrics = true;    ///< metrics and score terms/gates/reasons
  bool events = false;
  bool recording = false;  ///< decompressed recording bytes
};

/// One attempt, or nullopt when no attempt has that id.
DbResult<std::optional<AttemptRecord>> load_attempt(Database& db, std::int64_t attempt_id,
                                                    const AttemptDetail& detail = {true, true,
                                                                                   true});

/// Which attempts list_attempts returns.
struct AttemptFilter {
  std::optional<std::string> trainee_id;  ///< only this trainee's attempts
  std::optional<std::string> module_id;   ///< only attempts at this module
  bool include_practice = true;           ///< attempts without a trainee
};

/// Attempts in start order (started_utc, then id).
DbResult<std::vector<AttemptRecord>> list_attempts(Database& db, const AttemptFilter& filter = {},
                                                   const AttemptDetail& detail = {});

}  // namespace acdr
