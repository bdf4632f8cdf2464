// The side file of a finished attempt whose record could not be written (the database locked by
// another process for longer than we waited, the disk full, an I/O error): the complete outcome
// (metrics, score, events, recording, end time) is kept next to the database, in a file of its
// own, and stored into the record by the next program that opens it for writing (open_store).
// So a finished attempt is never lost, and never turned into an aborted one, because its final
// commit failed.
//
// Name: "<database file>.attempt-<id>.unsaved", in the database's directory (if that cannot be
// written: unsaved_fallback_directory()). Written atomically
// (a temporary file in the same directory, fsync, rename, fsync of the directory): a crash
// leaves either no side file or a complete one. Format "acdr-unsaved-attempt" version 1,
// little-endian, exact (doubles as their bit patterns), ending in the CRC-32 (zlib's) of
// everything before it, so a damaged file is refused rather than misread:
//   magic "acdr-unsaved-attempt\n", u32 version,
//   i64 attempt id, str attempt uuid, str ended_utc, f64 duration_s,
//   u32 n, n x (str name, f64 value)                                  metrics
//   f64 score, u8 passed,
//   u32 n, n x (str metric, f64 value, f64 score)                      score terms
//   u32 n, n x (str metric, f64 value, f64 max, u8 passed)             gates
//   u32 n, n x str                                                     reasons
//   u32 n, n x (f64 t_s, str kind, str zone, f64 value, str detail, i32 zone_index)  events
//   u8 has recording; if 1: str format, i64 frame_count, u64 raw size,
//                           u64 n, n bytes (the recording, zlib as in the record)
//   u32 CRC-32
// where str is u32 length + UTF-8 bytes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "db/db_result.hpp"
#include "db/records.hpp"
#include "db/xapi.hpp"

namespace acdr {

class Database;

/// A finished attempt's outcome waiting to be stored.
struct UnsavedOutcome {
  std::int64_t attempt_id = 0;
  std::string attempt_uuid;  ///< the attempt it belongs to (ids alone could match another file)
  AttemptOutcome outcome;    ///< ended_utc is always set: the attempt's real end
};

/// Where the side file of attempt `attempt_id` of the record at `db_path` lives.
std::string unsaved_outcome_path(const std::string& db_path, std::int64_t attempt_id);

/// Where a side file goes when it cannot be written next to the database (the disk that is
/// full is usually the database's): $XDG_STATE_HOME/acdr/unsaved if that is set (absolute),
/// else ~/.local/state/acdr/unsaved. There its name starts with the CRC-32 of the database's
/// absolute path in hex: "<crc>.attempt-<id>.unsaved".
std::string unsaved_fallback_directory();

/// Writes `unsaved` atomically to unsaved_outcome_path(), or, when that fails, to the fallback
/// directory; returns the path written, or an error naming both files and what failed (then no
/// side file exists).
DbResult<std::string> write_unsaved_outcome(const std::string& db_path,
                                            const UnsavedOutcome& unsaved);

/// Reads a side file back exactly as written. A truncated, damaged or foreign file is an error
/// naming the file, the byte offset and what was expected.
DbResult<UnsavedOutcome> read_unsaved_outcome(const std::string& path);

/// The side files waiting for the record at `db_path` (next to it and in the fallback
/// directory), in attempt order.
std::vector<std::string> find_unsaved_outcomes(const std::string& db_path);

/// What store_unsaved_outcomes did.
struct UnsavedReplay {
  std::vector<std::string> notes;           ///< one line per side file, for the user
  std::vector<std::int64_t> still_pending;  ///< attempts whose side file is still waiting
};

/// Stores every waiting side file of `db` into it (finish_attempt), removing each once its
/// attempt is completed in the record. A side file that cannot be stored yet (the database
/// busy again) stays, and its attempt is listed in still_pending so that it is not taken for
/// an interrupted one; one that does not belong to this record, or is damaged, stays and is
/// named in the notes.
UnsavedReplay store_unsaved_outcomes(Database& db);

/// How the final record of a finished attempt went.
struct FinalRecord {
  bool stored = false;    ///< completed in the record
  std::string side_file;  ///< not stored: the side file that keeps the outcome ("" if none)
  std::string error;      ///< not stored: why (the database's error, then the side file's)
};

/// Stores a finished attempt: finish_attempt_patiently (attempt_store.hpp) for up to
/// `patience_s`; when the record still cannot be written, the outcome (with its end time) goes
/// to the side file, to be stored at the next start. `xapi` as for finish_attempt.
FinalRecord finish_attempt_or_keep(Database& db, std::int64_t attempt_id, AttemptOutcome outcome,
                                   double patience_s, const XapiOptions& xapi = {});

}  // namespace acdr
