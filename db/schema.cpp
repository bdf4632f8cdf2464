// Schema v1 of the training record and the migration runner: see schema.hpp.
//
// Conventions of the schema:
// - STRICT tables: a value of the wrong type is an error, not silently converted.
// - Times are UTC ISO 8601 text with milliseconds ("2024-05-01T09:30:00.000Z"), which sorts
//   lexicographically in time order.
// - REAL columns that may receive NaN are nullable: SQLite stores NaN as NULL, and the store
//   reads NULL back as NaN.
// - Child rows (metrics, events, recordings, score details) cascade with their attempt; an
//   attempt cannot be deleted while trainees or modules point at it the other way round.
#include "db/schema.hpp"

#include <string>

#include "db/database.hpp"

namespace acdr {

namespace {

constexpr const char* kSchemaV1 = R"sql(
-- Who trains. The id is opaque (an institution's pseudonymous code); no personal data needed.
CREATE TABLE trainees (
  id           TEXT PRIMARY KEY NOT NULL CHECK (length(id) > 0),
  display_name TEXT NOT NULL DEFAULT '',
  created_utc  TEXT NOT NULL
) STRICT;

-- An ordered list of modules.
CREATE TABLE curricula (
  id    TEXT PRIMARY KEY NOT NULL CHECK (length(id) > 0),
  title TEXT NOT NULL DEFAULT ''
) STRICT;

-- A graded module: one scenario file with its pass rule. `version` increases by one each time
-- the module is registered with a different scenario hash.
CREATE TABLE modules (
  id                     TEXT PRIMARY KEY NOT NULL CHECK (length(id) > 0),
  curriculum_id          TEXT REFERENCES curricula(id) ON DELETE SET NULL,
  position               INTEGER NOT NULL DEFAULT 0,
  title                  TEXT NOT NULL DEFAULT '',
  scenario_path          TEXT NOT NULL DEFAULT '',
  scenario_hash          TEXT NOT NULL DEFAULT '',
  version                INTEGER NOT NULL DEFAULT 1 CHECK (version >= 1),
  -- 0: the prerequisites are the module(s) just before this one in its curriculum;
  -- 1: exactly the rows of module_prerequisites (possibly none).
  explicit_prerequisites INTEGER NOT NULL DEFAULT 0 CHECK (explicit_prerequisites IN (0, 1)),
  consecutive_passes     INTEGER NOT NULL DEFAULT 2 CHECK (consecutive_passes >= 1),
  pass_score             REAL NOT NULL DEFAULT 50.0
) STRICT;
CREATE INDEX modules_by_curriculum ON modules(curriculum_id, position);

-- Explicit prerequisites. The prerequisite is not a foreign key so modules can be registered in
-- any order; an unknown prerequisite keeps the module locked and says so.
CREATE TABLE module_prerequisites (
  module_id       TEXT NOT NULL REFERENCES modules(id) ON DELETE CASCADE,
  prerequisite_id TEXT NOT NULL CHECK (length(prerequisite_id) > 0),
  PRIMARY KEY (module_id, prerequisite_id),
  CHECK (module_id <> prerequisite_id)
) STRICT, WITHOUT ROWID;

-- One attempt at a module. trainee_id NULL = practice attempt (never counts for progression).
-- registration: xAPI/cmi5 registration UUID, shared by a trainee's attempts at one module.
-- writer_*: the process writing a running attempt (attempt_store.hpp: the abort rule).
CREATE TABLE attempts (
  id              INTEGER PRIMARY KEY,
  uuid            TEXT NOT NULL UNIQUE,
  registration    TEXT NOT NULL,
  trainee_id      TEXT REFERENCES trainees(id) ON DELETE RESTRICT,
  module_id       TEXT NOT NULL REFERENCES modules(id) ON DELETE RESTRICT,
  status          TEXT NOT NULL DEFAULT 'running'
                  CHECK (status IN ('running', 'completed', 'aborted')),
  started_utc     TEXT NOT NULL,
  ended_utc       TEXT,
  heartbeat_utc   TEXT NOT NULL,
  duration_s      REAL,
  input_device    TEXT NOT NULL DEFAULT '',
  program_version TEXT NOT NULL DEFAULT '',
  scenario_hash   TEXT NOT NULL DEFAULT '',
  override_lock   INTEGER NOT NULL DEFAULT 0 CHECK (override_lock IN (0, 1)),
  override_by     TEXT NOT NULL DEFAULT '',
  override_reason TEXT NOT NULL DEFAULT '',
  score           REAL,
  passed          INTEGER CHECK (passed IN (0, 1)),
  abort_reason    TEXT NOT NULL DEFAULT '',
  writer_pid      INTEGER NOT NULL,
  writer_start    INTEGER NOT NULL DEFAULT 0,
  writer_host     TEXT NOT NULL,
  CHECK (status <> 'completed' OR (ended_utc IS NOT NULL AND passed IS NOT NULL)),
  CHECK (override_lock = 0 OR length(override_by) > 0)
) STRICT;
CREATE INDEX attempts_by_trainee ON attempts(trainee_id, module_id, started_utc);
CREATE INDEX attempts_by_module ON attempts(module_id, started_utc);
CREATE INDEX attempts_running ON attempts(status) WHERE status = 'running';

-- A finished or aborted attempt is history: its status never changes again.
CREATE TRIGGER attempts_status_is_final
BEFORE UPDATE OF status ON attempts
WHEN OLD.status <> 'running' AND NEW.status <> OLD.status
BEGIN
  SELECT RAISE(ABORT, 'attempt status is final once completed or aborted');
END;

-- Named metric values in the order the assessment produced them.
CREATE TABLE metrics (
  attempt_id INTEGER NOT NULL REFERENCES attempts(id) ON DELETE CASCADE,
  name       TEXT NOT NULL,
  position   INTEGER NOT NULL,
  value      REAL,
  PRIMARY KEY (attempt_id, name)
) STRICT, WITHOUT ROWID;

-- The composite score's terms, the safety gates and the reasons for a fail (ScoreResult).
CREATE TABLE score_terms (
  attempt_id INTEGER NOT NULL REFERENCES attempts(id) ON DELETE CASCADE,
  position   INTEGER NOT NULL,
  metric     TEXT NOT NULL,
  value      REAL,
  score      REAL,
  PRIMARY KEY (attempt_id, position)
) STRICT, WITHOUT ROWID;
CREATE TABLE score_gates (
  attempt_id INTEGER NOT NULL REFERENCES attempts(id) ON DELETE CASCADE,
  position   INTEGER NOT NULL,
  metric     TEXT NOT NULL,
  value      REAL,
  max        REAL,
  passed     INTEGER NOT NULL CHECK (passed IN (0, 1)),
  PRIMARY KEY (attempt_id, position)
) STRICT, WITHOUT ROWID;
CREATE TABLE score_reasons (
  attempt_id INTEGER NOT NULL REFERENCES attempts(id) ON DELETE CASCADE,
  position   INTEGER NOT NULL,
  reason     TEXT NOT NULL,
  PRIMARY KEY (attempt_id, position)
) STRICT, WITHOUT ROWID;

-- Timed events of an attempt (zone warnings, overloads, numerical trouble).
CREATE TABLE events (
  attempt_id INTEGER NOT NULL REFERENCES attempts(id) ON DELETE CASCADE,
  seq        INTEGER NOT NULL,
  t_s        REAL,
  kind       TEXT NOT NULL,
  zone       TEXT NOT NULL DEFAULT '',
  value      REAL,
  detail     TEXT NOT NULL DEFAULT '',
  PRIMARY KEY (attempt_id, seq)
) STRICT, WITHOUT ROWID;

-- The input and frame stream of an attempt, enough to replay and re-score it. `format` names
-- the byte layout (owned by whoever writes it); `encoding` how the bytes are stored;
-- `complete` 0 = a checkpoint of a running or aborted attempt.
CREATE TABLE recordings (
  attempt_id  INTEGER PRIMARY KEY REFERENCES attempts(id) ON DELETE CASCADE,
  format      TEXT NOT NULL,
  encoding    TEXT NOT NULL CHECK (encoding IN ('zlib', 'identity')),
  frame_count INTEGER NOT NULL CHECK (frame_count >= 0),
  raw_bytes   INTEGER NOT NULL CHECK (raw_bytes >= 0),
  complete    INTEGER NOT NULL CHECK (complete IN (0, 1)),
  data        BLOB NOT NULL
) STRICT;
)sql";

// v2: an event's zone is NULL when the event is not about a zone (v1 stored ''), and keeps the
// zone's index in the recording's zone list; recordings of running attempts are checkpointed
// piece by piece (recording_chunks), each piece compressed on its own, so a checkpoint costs
// what is new rather than the whole attempt so far.
constexpr const char* kSchemaV2 = R"sql(
CREATE TABLE events_v2 (
  attempt_id INTEGER NOT NULL REFERENCES attempts(id) ON DELETE CASCADE,
  seq        INTEGER NOT NULL,
  t_s        REAL,
  kind       TEXT NOT NULL,
  zone       TEXT CHECK (zone IS NULL OR length(zone) > 0),
  zone_index INTEGER CHECK (zone_index IS NULL OR zone_index >= 0),
  value      REAL,
  detail     TEXT NOT NULL DEFAULT '',
  PRIMARY KEY (attempt_id, seq)
) STRICT, WITHOUT ROWID;
INSERT INTO events_v2 (attempt_id, seq, t_s, kind, zone, zone_index, value, detail)
  SELECT attempt_id, seq, t_s, kind, NULLIF(zone, ''), NULL, value, detail FROM events;
DROP TABLE events;
ALTER TABLE events_v2 RENAME TO events;

-- Pieces of the recording of a running (later: aborted) attempt, in order. Their uncompressed
-- bytes concatenate to the recording; finishing the attempt replaces them by one row of
-- `recordings`.
CREATE TABLE recording_chunks (
  id          INTEGER PRIMARY KEY,
  attempt_id  INTEGER NOT NULL REFERENCES attempts(id) ON DELETE CASCADE,
  seq         INTEGER NOT NULL CHECK (seq >= 0),
  format      TEXT NOT NULL,
  encoding    TEXT NOT NULL CHECK (encoding IN ('zlib', 'identity')),
  frame_count INTEGER NOT NULL CHECK (frame_count >= 0),
  raw_bytes   INTEGER NOT NULL CHECK (raw_bytes >= 0),
  data        BLOB NOT NULL,
  UNIQUE (attempt_id, seq)
) STRICT;
)sql";

// v3: the outbox of xAPI statements for a learning record store (db/outbox.hpp). Finishing an
// attempt queues its statements in the same transaction; a sender marks them sent (or failed,
// with the store's answer) later. The statement text is kept as queued: what is sent is what
// was stored, even if the attempt is re-scored afterwards.
constexpr const char* kSchemaV3 = R"sql(
CREATE TABLE xapi_outbox (
  id           INTEGER PRIMARY KEY,
  statement_id TEXT NOT NULL UNIQUE CHECK (length(statement_id) = 36),
  attempt_id   INTEGER NOT NULL REFERENCES attempts(id) ON DELETE CASCADE,
  statement    TEXT NOT NULL CHECK (json_valid(statement)),
  queued_utc   TEXT NOT NULL,
  state        TEXT NOT NULL DEFAULT 'queued' CHECK (state IN ('queued', 'sent', 'failed')),
  tries        INTEGER NOT NULL DEFAULT 0 CHECK (tries >= 0),
  last_try_utc TEXT,
  last_error   TEXT NOT NULL DEFAULT '',
  sent_utc     TEXT,
  sent_to      TEXT NOT NULL DEFAULT '',
  CHECK (state <> 'sent' OR sent_utc IS NOT NULL)
) STRICT;
CREATE INDEX xapi_outbox_queued ON xapi_outbox(id) WHERE state = 'queued';
CREATE INDEX xapi_outbox_by_attempt ON xapi_outbox(attempt_id);
)sql";

// v4: the real-time factor of an attempt (simulated seconds per second of the wall clock over
// the attempt; below 1 the trainee saw slow motion). NULL for attempts stored before it was
// kept, and for those that do not know it.
constexpr const char* kSchemaV4 = R"sql(
ALTER TABLE attempts ADD COLUMN realtime_factor REAL
  CHECK (realtime_factor IS NULL OR realtime_factor > 0);
)sql";

constexpr Migration kMigrations[] = {
    {1, "training record v1: trainees, curricula, modules, attempts, metrics, events, recordings",
     kSchemaV1},
    {2, "events with NULL zone and zone index; recording chunks for checkpoints", kSchemaV2},
    {3, "outbox of xAPI statements for a learning record store", kSchemaV3},
    {4, "real-time factor of an attempt", kSchemaV4},
};

static_assert(std::size(kMigrations) == kSchemaVersion,
              "one migration per schema version, in order");

struct FileStamp {
  std::int64_t application_id = 0;
  std::int64_t user_version = 0;
};

DbResult<FileStamp> read_stamp(Database& db) {
  DbResult<std::int64_t> app = db.pragma_int("application_id");
  if (!app) return app.error();
  DbResult<std::int64_t> version = db.pragma_int("user_version");
  if (!version) return version.error();
  return FileStamp{app.value(), version.value()};
}

DbStatus refuse_unknown(const Database& db, const FileStamp& stamp) {
  if (stamp.user_version > kSchemaVersion) {
    return DbError{db.path() + ": the record has schema version " +
                       std::to_string(stamp.user_version) +
                       ", newer than this program knows (" + std::to_string(kSchemaVersion) +
                       "); use a newer acdr. The file was not changed.",
                   0};
  }
  if (stamp.application_id != 0 && stamp.application_id != kApplicationId) {
    return DbError{db.path() + ": not an ACDR record (PRAGMA application_id is " +
                       std::to_string(stamp.application_id) + ", expected " +
                       std::to_string(kApplicationId) + "); refusing to change it. The file was not changed.",
                   0};
  }
  if (stamp.user_version < 0) {
    return DbError{db.path() + ": invalid schema version " + std::to_string(stamp.user_version) +
                       " (expected 0.." + std::to_string(kSchemaVersion) + ")",
                   0};
  }
  return {};
}

// Tables, views, indexes and triggers other than SQLite's own.
DbResult<std::int64_t> count_own_tables(Database& db) {
  DbResult<Statement> count = db.prepare(
      "SELECT count(*) FROM sqlite_schema WHERE name NOT LIKE 'sqlite\\_%' ESCAPE '\\'");
  if (!count) return count.error();
  DbResult<bool> row = count->step();
  if (!row) return row.error();
  return count->column_int64(0);
}

DbError not_a_record(const Database& db) {
  return DbError{db.path() +
                     ": not an ACDR record (it has tables but no ACDR schema version); "
                     "refusing to change it. The file was not changed.",
                 0};
}

}  // namespace

std::span<const Migration> schema_migrations() { return kMigrations; }

DbStatus check_schema_current(Database& db) {
  // One read transaction, so both stamps come from the same moment (see check_record_identity).
  DbResult<Transaction> tx = Transaction::begin(db, Transaction::Mode::kDeferred);
  if (!tx) return tx.error();
  DbResult<FileStamp> stamp = read_stamp(db);
  if (!stamp) return stamp.error();
  if (DbStatus s = refuse_unknown(db, stamp.value()); !s) return s;
  if (stamp->user_version != kSchemaVersion || stamp->application_id != kApplicationId) {
    return DbError{db.path() + ": the record has schema version " +
                       std::to_string(stamp->user_version) + ", expected " +
                       std::to_string(kSchemaVersion) +
                       "; open it once read-write to upgrade it",
                   0};
  }
  return {};
}

DbStatus check_record_identity(Database& db, bool may_initialise) {
  // One read transaction: the stamp and the tables from the same moment. Read one by one, a
  // program creating the record at the same time could commit in between, and a version read
  // before its commit with tables counted after it looked like someone else's file.
  DbResult<Transaction> tx = Transaction::begin(db, Transaction::Mode::kDeferred);
  if (!tx) return tx.error();
  DbResult<FileStamp> stamp = read_stamp(db);
  if (!stamp) return stamp.error();
  if (DbStatus s = refuse_unknown(db, stamp.value()); !s) return s;
  if (stamp->user_version != 0) return {};  // an ACDR record; migrated if older
  DbResult<std::int64_t> tables = count_own_tables(db);
  if (!tables) return tables.error();
  if (tables.value() != 0) return not_a_record(db);
  if (!may_initialise) {
    return DbError{db.path() +
                       ": an empty file, not an ACDR record yet; a command that only reads "
                       "does not start a record (`acdr run --db " +
                       db.path() + " ...` does). The file was not changed.",
                   0};
  }
  return {};
}

DbStatus migrate_schema(Database& db) {
  // Fast path without the write lock: already current.
  DbResult<FileStamp> stamp = read_stamp(db);
  if (!stamp) return stamp.error();
  if (DbStatus s = refuse_unknown(db, stamp.value()); !s) return s;
  if (stamp->user_version == kSchemaVersion && stamp->application_id == kApplicationId) return {};

  DbResult<Transaction> tx = Transaction::begin(db, Transaction::Mode::kImmediate);
  if (!tx) return tx.error();
  // Read again under the lock: another process may have migrated in between.
  stamp = read_stamp(db);
  if (!stamp) return stamp.error();
  if (DbStatus s = refuse_unknown(db, stamp.value()); !s) return s;

  if (stamp->user_version == 0) {
    // Version 0 is a new file only if it is empty; tables without our stamp belong to someone
    // else.
    DbResult<std::int64_t> tables = count_own_tables(db);
    if (!tables) return tables.error();
    if (tables.value() != 0) return not_a_record(db);
  }

  for (const Migration& m : kMigrations) {
    if (m.version <= stamp->user_version) continue;
    if (DbStatus s = db.exec(m.sql); !s) {
      return DbError{db.path() + ": migration to schema version " + std::to_string(m.version) +
                         " (" + m.description + ") failed: " + s.error().message,
                     s.error().sqlite_code};
    }
    // Pragmas take no bound parameters; the value is the program's own constant.
    if (DbStatus s = db.exec("PRAGMA user_version = " + std::to_string(m.version)); !s) return s;
  }
  if (DbStatus s = db.exec("PRAGMA application_id = " + std::to_string(kApplicationId)); !s) {
    return s;
  }
  return tx->commit();
}

}  // namespace acdr
