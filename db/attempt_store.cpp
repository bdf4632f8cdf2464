// Attempt lifecycle and reading attempts back: see attempt_store.hpp.
#include "db/attempt_store.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include "db/outcome_side_file.hpp"
#include "db/outbox.hpp"
#include "db/recording_codec.hpp"
#include "db/utc_time.hpp"
#include "db/uuid.hpp"
#include "db/writer_identity.hpp"

namespace acdr {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

constexpr const char* kAttemptColumns =
    "id, uuid, registration, trainee_id, module_id, status, started_utc, ended_utc, "
    "heartbeat_utc, duration_s, input_device, program_version, scenario_hash, override_lock, "
    "override_by, override_reason, score, passed, abort_reason, writer_pid, writer_host, "
    "realtime_factor";

std::string attempt_where(const Database& db, std::int64_t id) {
  return db.path() + ": attempt " + std::to_string(id) + ": ";
}

// SQLite stores NaN as NULL; read it back as NaN so a metric that blew up stays visible.
double read_real(const Statement& s, int column) {
  return s.column_is_null(column) ? kNaN : s.column_double(column);
}

DbResult<AttemptStatus> read_status(Database& db, std::int64_t id) {
  DbResult<Statement> s = db.prepare("SELECT status FROM attempts WHERE id = ?");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(id); !b) return b.error();
  DbResult<bool> row = s->step();
  if (!row) return row.error();
  if (!row.value()) return DbError{attempt_where(db, id) + "no such attempt", 0};
  const std::string text = s->column_text(0);
  std::optional<AttemptStatus> status = parse_attempt_status(text);
  if (!status) {
    return DbError{attempt_where(db, id) + "unknown status '" + text +
                       "' (expected running, completed or aborted)",
                   0};
  }
  return *status;
}

DbStatus require_running(Database& db, std::int64_t id, const char* action) {
  DbResult<AttemptStatus> status = read_status(db, id);
  if (!status) return status.error();
  if (status.value() != AttemptStatus::kRunning) {
    return DbError{attempt_where(db, id) + "cannot " + action + ": it is already " +
                       attempt_status_name(status.value()) + " (expected running)",
                   0};
  }
  return {};
}

DbStatus run_with(Database& db, const char* sql, std::int64_t id) {
  DbResult<Statement> s = db.prepare(sql);
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(id); !b) return b;
  return s->run();
}

// Runs `sql`, whose one parameter is the attempt id, calling `on_row(statement)` for each row.
template <class OnRow>
DbStatus each_attempt_row(Database& db, const char* sql, std::int64_t id, OnRow on_row) {
  DbResult<Statement> s = db.prepare(sql);
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(id); !b) return b;
  return s->for_each_row([&] { return on_row(*s); });
}

// Inserts `events` numbered from `first_seq` on.
DbStatus insert_events(Database& db, std::int64_t id, const std::vector<EventRecord>& events,
                       std::int64_t first_seq) {
  DbResult<Statement> s = db.prepare(
      "INSERT INTO events (attempt_id, seq, t_s, kind, zone, zone_index, value, detail) "
      "VALUES (?, ?, ?, ?, ?, ?, ?, ?)");
  if (!s) return s.error();
  return s->run_for_each(
      events,
      [&](std::size_t i, const EventRecord& e) {
        // Not about a zone: NULL, not '' or -1.
        const std::optional<std::string> zone =
            e.zone.empty() ? std::nullopt : std::optional<std::string>(e.zone);
        const std::optional<std::int64_t> zone_index =
            e.zone_index >= 0 ? std::optional<std::int64_t>(e.zone_index) : std::nullopt;
        return s->bind_all(id, first_seq + static_cast<std::int64_t>(i), e.t_s, e.kind, zone,
                           zone_index, e.value, e.detail);
      },
      [&](std::size_t i) {
        return attempt_where(db, id) + "event " + std::to_string(first_seq + i);
      });
}

DbStatus write_events(Database& db, std::int64_t id, const std::vector<EventRecord>& events) {
  if (DbStatus d = run_with(db, "DELETE FROM events WHERE attempt_id = ?", id); !d) return d;
  return insert_events(db, id, events, 0);
}

// A recording compressed before its transaction starts: compressing a long attempt takes
// seconds, and the write lock should be held only for the write.
struct PackedRecording {
  const RecordingData* source = nullptr;
  std::vector<std::uint8_t> data;
};

DbResult<std::optional<PackedRecording>> pack_recording(const Database& db, std::int64_t id,
                                                        const RecordingData* recording) {
  if (recording == nullptr) return std::optional<PackedRecording>();
  if (recording->frame_count < 0) {
    return DbError{attempt_where(db, id) + "recording frame_count is " +
                       std::to_string(recording->frame_count) + " (expected >= 0)",
                   0};
  }
  DbResult<std::vector<std::uint8_t>> packed = compress_recording(recording->bytes);
  if (!packed) return DbError{attempt_where(db, id) + packed.error().message, 0};
  return std::optional<PackedRecording>(PackedRecording{recording, std::move(packed.value())});
}

DbStatus write_recording(Database& db, std::int64_t id, const PackedRecording& packed,
                         bool complete) {
  const RecordingData& recording = *packed.source;
  DbResult<Statement> s = db.prepare(
      "INSERT INTO recordings (attempt_id, format, encoding, frame_count, raw_bytes, complete, "
      "data) VALUES (?, ?, 'zlib', ?, ?, ?, ?) "
      "ON CONFLICT (attempt_id) DO UPDATE SET format = excluded.format, "
      "encoding = excluded.encoding, frame_count = excluded.frame_count, "
      "raw_bytes = excluded.raw_bytes, complete = excluded.complete, data = excluded.data");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(id, recording.format, recording.frame_count,
                               static_cast<std::int64_t>(recording.bytes.size()), complete,
                               BlobView(packed.data));
      !b) {
    return b;
  }
  return s->run();
}

DbStatus write_assessment(Database& db, std::int64_t id, const Metrics& metrics,
                          const ScoreResult& score) {
  for (const char* sql : {"DELETE FROM metrics WHERE attempt_id = ?",
                          "DELETE FROM score_terms WHERE attempt_id = ?",
                          "DELETE FROM score_gates WHERE attempt_id = ?",
                          "DELETE FROM score_reasons WHERE attempt_id = ?"}) {
    if (DbStatus d = run_with(db, sql, id); !d) return d;
  }
  const auto pos = [](std::size_t i) { return static_cast<std::int64_t>(i); };
  const auto row_name = [&](const char* table) {
    return [&db, id, table](std::size_t i) {
      return attempt_where(db, id) + table + " row " + std::to_string(i);
    };
  };
  DbResult<Statement> s =
      db.prepare("INSERT INTO metrics (attempt_id, name, position, value) VALUES (?, ?, ?, ?)");
  if (!s) return s.error();
  if (DbStatus d = s->run_for_each(
          metrics.values,
          [&](std::size_t i, const auto& m) { return s->bind_all(id, m.first, pos(i), m.second); },
          [&](std::size_t i) {
            return attempt_where(db, id) + "metric '" + metrics.values[i].first + "'";
          });
      !d) {
    return d;
  }
  s = db.prepare(
      "INSERT INTO score_terms (attempt_id, position, metric, value, score) "
      "VALUES (?, ?, ?, ?, ?)");
  if (!s) return s.error();
  if (DbStatus d = s->run_for_each(
          score.terms,
          [&](std::size_t i, const TermScore& t) {
            return s->bind_all(id, pos(i), t.metric, t.value, t.score);
          },
          row_name("score term"));
      !d) {
    return d;
  }
  s = db.prepare(
      "INSERT INTO score_gates (attempt_id, position, metric, value, max, passed) "
      "VALUES (?, ?, ?, ?, ?, ?)");
  if (!s) return s.error();
  if (DbStatus d = s->run_for_each(
          score.gates,
          [&](std::size_t i, const GateResult& g) {
            return s->bind_all(id, pos(i), g.metric, g.value, g.max, g.passed);
          },
          row_name("score gate"));
      !d) {
    return d;
  }
  s = db.prepare("INSERT INTO score_reasons (attempt_id, position, reason) VALUES (?, ?, ?)");
  if (!s) return s.error();
  return s->run_for_each(
      score.reasons,
      [&](std::size_t i, const std::string& reason) { return s->bind_all(id, pos(i), reason); },
      row_name("score reason"));
}

AttemptRecord read_attempt_row(const Statement& s) {
  AttemptRecord a;
  a.id = s.column_int64(0);
  a.uuid = s.column_text(1);
  a.registration = s.column_text(2);
  a.trainee_id = s.column_optional_text(3);
  a.module_id = s.column_text(4);
  // The CHECK constraint allows only the three names.
  a.status = parse_attempt_status(s.column_text(5)).value_or(AttemptStatus::kRunning);
  a.started_utc = s.column_text(6);
  a.ended_utc = s.column_optional_text(7);
  a.heartbeat_utc = s.column_text(8);
  a.duration_s = s.column_optional_double(9);
  a.input_device = s.column_text(10);
  a.program_version = s.column_text(11);
  a.scenario_hash = s.column_text(12);
  a.override_lock = s.column_int64(13) != 0;
  a.override_by = s.column_text(14);
  a.override_reason = s.column_text(15);
  a.score = s.column_optional_double(16);
  if (!s.column_is_null(17)) a.passed = s.column_int64(17) != 0;
  a.abort_reason = s.column_text(18);
  a.writer_pid = s.column_int64(19);
  a.writer_host = s.column_text(20);
  a.realtime_factor = s.column_optional_double(21);
  a.score_detail.score = a.score.value_or(0.0);
  a.score_detail.passed = a.passed.value_or(false);
  return a;
}

DbResult<std::vector<std::uint8_t>> unpack(const Database& db, std::int64_t id,
                                           const std::string& encoding,
                                           std::vector<std::uint8_t> data,
                                           std::int64_t raw_bytes) {
  if (encoding != "zlib") return data;
  DbResult<std::vector<std::uint8_t>> raw =
      decompress_recording(data, static_cast<std::uint64_t>(raw_bytes));
  if (!raw) return DbError{attempt_where(db, id) + raw.error().message, 0};
  return raw;
}

// The checkpointed pieces of a recording, concatenated (nullopt when there are none).
DbResult<std::optional<RecordingData>> read_chunks(Database& db, std::int64_t id) {
  std::optional<RecordingData> out;
  if (DbStatus r = each_attempt_row(
          db,
          "SELECT seq, format, encoding, frame_count, raw_bytes, data FROM recording_chunks "
          "WHERE attempt_id = ? ORDER BY seq",
          id,
          [&](const Statement& s) -> DbStatus {
            const std::string format = s.column_text(1);
            if (!out) {
              out.emplace();
              out->format = format;
              out->complete = false;
            } else if (format != out->format) {
              return DbError{attempt_where(db, id) + "recording chunk " +
                                 std::to_string(s.column_int64(0)) + " has format '" + format +
                                 "' (expected '" + out->format + "' like the first)",
                             0};
            }
            out->frame_count += s.column_int64(3);
            DbResult<std::vector<std::uint8_t>> raw =
                unpack(db, id, s.column_text(2), s.column_blob(5), s.column_int64(4));
            if (!raw) return raw.error();
            out->bytes.insert(out->bytes.end(), raw->begin(), raw->end());
            return {};
          });
      !r) {
    return r.error();
  }
  return out;
}

DbStatus read_details(Database& db, AttemptRecord& a, const AttemptDetail& detail) {
  if (detail.metrics) {
    const auto read = [&](const char* sql, auto on_row) {
      return each_attempt_row(db, sql, a.id, on_row);
    };
    if (DbStatus r = read("SELECT name, value FROM metrics WHERE attempt_id = ? ORDER BY position",
                          [&](const Statement& s) {
                            a.metrics.values.emplace_back(s.column_text(0), read_real(s, 1));
                          });
        !r) {
      return r;
    }
    if (DbStatus r = read("SELECT metric, value, score FROM score_terms WHERE attempt_id = ? "
                          "ORDER BY position",
                          [&](const Statement& s) {
                            a.score_detail.terms.push_back(
                                TermScore{s.column_text(0), read_real(s, 1), read_real(s, 2)});
                          });
        !r) {
      return r;
    }
    if (DbStatus r =
            read("SELECT metric, value, max, passed FROM score_gates "
                 "WHERE attempt_id = ? ORDER BY position",
                 [&](const Statement& s) {
                   a.score_detail.gates.push_back(GateResult{
                       s.column_text(0), read_real(s, 1), read_real(s, 2), s.column_int64(3) != 0});
                 });
        !r) {
      return r;
    }
    if (DbStatus r =
            read("SELECT reason FROM score_reasons WHERE attempt_id = ? "
                 "ORDER BY position",
                 [&](const Statement& s) { a.score_detail.reasons.push_back(s.column_text(0)); });
        !r) {
      return r;
    }
  }
  if (detail.events) {
    if (DbStatus r = each_attempt_row(
            db,
            "SELECT t_s, kind, zone, value, detail, zone_index FROM events "
            "WHERE attempt_id = ? ORDER BY seq",
            a.id,
            [&](const Statement& s) {
              a.events.push_back(EventRecord{
                  read_real(s, 0), s.column_text(1), s.column_optional_text(2).value_or(""),
                  read_real(s, 3), s.column_text(4),
                  s.column_is_null(5) ? -1 : static_cast<std::int32_t>(s.column_int64(5))});
            });
        !r) {
      return r;
    }
  }
  if (detail.recording) {
    DbResult<Statement> s = db.prepare(
        "SELECT format, encoding, frame_count, raw_bytes, complete, data FROM recordings "
        "WHERE attempt_id = ?");
    if (!s) return s.error();
    if (DbStatus b = s->bind_all(a.id); !b) return b;
    DbResult<bool> row = s->step();
    if (!row) return row.error();
    if (row.value()) {
      RecordingData r;
      r.format = s->column_text(0);
      const std::string encoding = s->column_text(1);
      r.frame_count = s->column_int64(2);
      const std::int64_t raw_bytes = s->column_int64(3);
      r.complete = s->column_int64(4) != 0;
      DbResult<std::vector<std::uint8_t>> raw =
          unpack(db, a.id, encoding, s->column_blob(5), raw_bytes);
      if (!raw) return raw.error();
      r.bytes = std::move(raw.value());
      a.recording = std::move(r);
    } else {
      DbResult<std::optional<RecordingData>> chunks = read_chunks(db, a.id);
      if (!chunks) return chunks.error();
      a.recording = std::move(chunks.value());
    }
  }
  return {};
}

}  // namespace

DbResult<Database> open_store(const std::string& path, const OpenOptions& options,
                              std::vector<std::string>* notes) {
  DbResult<Database> db = Database::open(path, options);
  if (!db) return db;
  if (!options.read_only) {
    // Finished attempts first: their side files complete them, so they are not taken for
    // interrupted ones below.
    UnsavedReplay replay = store_unsaved_outcomes(db.value());
    if (notes) notes->insert(notes->end(), replay.notes.begin(), replay.notes.end());
    DbResult<std::vector<std::int64_t>> aborted =
        mark_interrupted_attempts(db.value(), replay.still_pending);
    if (!aborted) return aborted.error();
  }
  return db;
}

DbResult<std::int64_t> begin_attempt(Database& db, const AttemptStart& start) {
  if (start.module_id.empty()) {
    return DbError{db.path() + ": begin_attempt: module id is empty (expected a module id)", 0};
  }
  if (start.trainee_id && start.trainee_id->empty()) {
    return DbError{db.path() +
                       ": begin_attempt: trainee id is empty (expected an id, or none for a "
                       "practice attempt)",
                   0};
  }
  if (start.override_lock && start.override_by.empty()) {
    return DbError{db.path() +
                       ": begin_attempt: an override needs the name of who decided it "
                       "(override_by is empty)",
                   0};
  }
  std::string started = start.started_utc;
  if (started.empty()) {
    started = utc_now_text();
  } else if (!parse_utc(started)) {
    return DbError{db.path() + ": begin_attempt: started_utc '" + started +
                       "' is not UTC ISO 8601 (expected e.g. 2024-05-01T09:30:00.000Z)",
                   0};
  }

  DbResult<Transaction> tx = Transaction::begin(db);
  if (!tx) return tx.error();

  {
    DbResult<Statement> s = db.prepare("SELECT 1 FROM modules WHERE id = ?");
    if (!s) return s.error();
    if (DbStatus b = s->bind_all(start.module_id); !b) return b.error();
    DbResult<bool> row = s->step();
    if (!row) return row.error();
    if (!row.value()) {
      return DbError{db.path() + ": begin_attempt: module '" + start.module_id +
                         "' is not registered (register it with upsert_module first)",
                     0};
    }
  }

  std::string registration;
  if (start.trainee_id) {
    DbResult<Statement> add = db.prepare(
        "INSERT INTO trainees (id, display_name, created_utc) VALUES (?, '', ?) "
        "ON CONFLICT (id) DO NOTHING");
    if (!add) return add.error();
    if (DbStatus b = add->bind_all(*start.trainee_id, started); !b) return b.error();
    if (DbStatus r = add->run(); !r) return r.error();

    // One cmi5 registration per trainee and module: the first attempt's.
    DbResult<Statement> reg = db.prepare(
        "SELECT registration FROM attempts WHERE trainee_id = ? AND module_id = ? "
        "ORDER BY id LIMIT 1");
    if (!reg) return reg.error();
    if (DbStatus b = reg->bind_all(*start.trainee_id, start.module_id); !b) return b.error();
    DbResult<bool> row = reg->step();
    if (!row) return row.error();
    if (row.value()) registration = reg->column_text(0);
  }
  if (registration.empty()) registration = make_uuid_v4();

  const WriterIdentity writer = current_writer();
  DbResult<Statement> s = db.prepare(
      "INSERT INTO attempts (uuid, registration, trainee_id, module_id, status, started_utc, "
      "heartbeat_utc, input_device, program_version, scenario_hash, override_lock, override_by, "
      "override_reason, writer_pid, writer_start, writer_host) "
      "VALUES (?, ?, ?, ?, 'running', ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(make_uuid_v4(), registration, start.trainee_id, start.module_id,
                               started, utc_now_text(), start.input_device,
                               start.program_version, start.scenario_hash, start.override_lock,
                               start.override_by, start.override_reason, writer.pid,
                               writer.start_ticks, writer.host);
      !b) {
    return b.error();
  }
  if (DbStatus r = s->run(); !r) return r.error();
  const std::int64_t id = db.last_insert_rowid();
  if (DbStatus c = tx->commit(); !c) return c.error();
  return id;
}

DbStatus checkpoint_attempt(Database& db, std::int64_t attempt_id,
                            const std::vector<EventRecord>& events,
                            const RecordingData* recording) {
  DbResult<std::optional<PackedRecording>> packed = pack_recording(db, attempt_id, recording);
  if (!packed) return packed.error();
  DbResult<Transaction> tx = Transaction::begin(db);
  if (!tx) return tx.error();
  if (DbStatus r = require_running(db, attempt_id, "checkpoint"); !r) return r;
  if (DbStatus w = write_events(db, attempt_id, events); !w) return w;
  if (packed.value()) {
    if (DbStatus w = write_recording(db, attempt_id, *packed.value(), false); !w) return w;
  }
  DbResult<Statement> s = db.prepare("UPDATE attempts SET heartbeat_utc = ? WHERE id = ?");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(utc_now_text(), attempt_id); !b) return b;
  if (DbStatus r = s->run(); !r) return r;
  return tx->commit();
}

DbStatus append_checkpoint(Database& db, std::int64_t attempt_id,
                           const AttemptCheckpoint& checkpoint) {
  // Compressed before the transaction: the write lock is held only for the write.
  DbResult<std::optional<PackedRecording>> packed =
      pack_recording(db, attempt_id, checkpoint.chunk ? &*checkpoint.chunk : nullptr);
  if (!packed) return packed.error();
  DbResult<Transaction> tx = Transaction::begin(db);
  if (!tx) return tx.error();
  if (DbStatus r = require_running(db, attempt_id, "checkpoint"); !r) return r;
  if (!checkpoint.new_events.empty()) {
    DbResult<Statement> next =
        db.prepare("SELECT coalesce(max(seq) + 1, 0) FROM events WHERE attempt_id = ?");
    if (!next) return next.error();
    if (DbStatus b = next->bind_all(attempt_id); !b) return b;
    DbResult<bool> row = next->step();
    if (!row) return row.error();
    const std::int64_t first = next->column_int64(0);
    if (DbStatus w = insert_events(db, attempt_id, checkpoint.new_events, first); !w) return w;
  }
  if (packed.value()) {
    const RecordingData& chunk = *checkpoint.chunk;
    DbResult<Statement> s = db.prepare(
        "INSERT INTO recording_chunks (attempt_id, seq, format, encoding, frame_count, raw_bytes, "
        "data) VALUES (?1, (SELECT coalesce(max(seq) + 1, 0) FROM recording_chunks "
        "WHERE attempt_id = ?1), ?2, 'zlib', ?3, ?4, ?5)");
    if (!s) return s.error();
    if (DbStatus b = s->bind_all(attempt_id, chunk.format, chunk.frame_count,
                                 static_cast<std::int64_t>(chunk.bytes.size()),
                                 BlobView(packed.value()->data));
        !b) {
      return b;
    }
    if (DbStatus r = s->run(); !r) return r;
  }
  if (checkpoint.metrics) {
    if (DbStatus w = write_assessment(db, attempt_id, *checkpoint.metrics, ScoreResult{}); !w) {
      return w;
    }
  }
  DbResult<Statement> s = db.prepare(
      "UPDATE attempts SET heartbeat_utc = ?, duration_s = coalesce(?, duration_s) WHERE id = ?");
  if (!s) return s.error();
  const std::optional<double> duration =
      checkpoint.duration_s >= 0.0 ? std::optional<double>(checkpoint.duration_s) : std::nullopt;
  if (DbStatus b = s->bind_all(utc_now_text(), duration, attempt_id); !b) return b;
  if (DbStatus r = s->run(); !r) return r;
  return tx->commit();
}

DbStatus finish_attempt(Database& db, std::int64_t attempt_id, const AttemptOutcome& outcome,
                        const XapiOptions& xapi) {
  std::string ended = outcome.ended_utc;
  if (ended.empty()) {
    ended = utc_now_text();
  } else if (!parse_utc(ended)) {
    return DbError{attempt_where(db, attempt_id) + "ended_utc '" + ended +
                       "' is not UTC ISO 8601 (expected e.g. 2024-05-01T09:30:00.000Z)",
                   0};
  }

  DbResult<std::optional<PackedRecording>> packed = pack_recording(
      db, attempt_id, outcome.recording ? &*outcome.recording : nullptr);
  if (!packed) return packed.error();

  // Everything below is one transaction: a crash leaves the attempt running (and later
  // aborted with its last checkpoint), never half-finished.
  DbResult<Transaction> tx = Transaction::begin(db);
  if (!tx) return tx.error();
  if (DbStatus r = require_running(db, attempt_id, "finish"); !r) return r;
  if (DbStatus w = write_assessment(db, attempt_id, outcome.metrics, outcome.score); !w) return w;
  if (DbStatus w = write_events(db, attempt_id, outcome.events); !w) return w;
  if (packed.value()) {
    if (DbStatus w = write_recording(db, attempt_id, *packed.value(), true); !w) return w;
    // The whole recording supersedes the checkpointed pieces.
    if (DbStatus d = run_with(db, "DELETE FROM recording_chunks WHERE attempt_id = ?", attempt_id);
        !d) {
      return d;
    }
  }
  const std::optional<double> duration =
      outcome.duration_s >= 0.0 ? std::optional<double>(outcome.duration_s) : std::nullopt;
  const std::optional<double> realtime_factor =
      std::isfinite(outcome.realtime_factor) && outcome.realtime_factor > 0.0
          ? std::optional<double>(outcome.realtime_factor)
          : std::nullopt;
  DbResult<Statement> s = db.prepare(
      "UPDATE attempts SET status = 'completed', ended_utc = ?, heartbeat_utc = ?, "
      "duration_s = ?, realtime_factor = ?, score = ?, passed = ? WHERE id = ?");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(ended, ended, duration, realtime_factor, outcome.score.score,
                               outcome.score.passed, attempt_id);
      !b) {
    return b;
  }
  if (DbStatus r = s->run(); !r) return r;
  // Its statements wait in the outbox from the same commit on.
  if (DbResult<int> q = queue_attempt_statements(db, attempt_id, xapi); !q) return q.error();
  return tx->commit();
}

DbStatus finish_attempt_patiently(Database& db, std::int64_t attempt_id,
                                  const AttemptOutcome& outcome, double patience_s,
                                  const XapiOptions& xapi) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::duration<double>(std::max(0.0, patience_s));
  const int usual_timeout_ms = db.busy_timeout_ms();
  for (;;) {
    // Each try waits (SQLite's busy handler) at most for what is left of the patience.
    const double left_s = std::chrono::duration<double>(deadline - Clock::now()).count();
    db.set_busy_timeout_ms(static_cast<int>(std::clamp(left_s * 1000.0, 0.0,
                                                       static_cast<double>(usual_timeout_ms))));
    DbStatus stored = finish_attempt(db, attempt_id, outcome, xapi);
    db.set_busy_timeout_ms(usual_timeout_ms);
    const int primary = stored ? 0 : (stored.error().sqlite_code & 0xff);
    const bool worth_retrying =
        primary == SQLITE_BUSY || primary == SQLITE_LOCKED || primary == SQLITE_FULL;
    if (stored || !worth_retrying || Clock::now() >= deadline) return stored;
    std::this_thread::sleep_for(std::chrono::milliseconds(primary == SQLITE_FULL ? 500 : 50));
  }
}

DbStatus abort_attempt(Database& db, std::int64_t attempt_id, const std::string& reason) {
  DbResult<Transaction> tx = Transaction::begin(db);
  if (!tx) return tx.error();
  if (DbStatus r = require_running(db, attempt_id, "abort"); !r) return r;
  const std::string now = utc_now_text();
  DbResult<Statement> s = db.prepare(
      "UPDATE attempts SET status = 'aborted', ended_utc = ?, heartbeat_utc = ?, "
      "abort_reason = ? WHERE id = ?");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(now, now, reason, attempt_id); !b) return b;
  if (DbStatus r = s->run(); !r) return r;
  return tx->commit();
}

DbResult<std::vector<std::int64_t>> mark_interrupted_attempts(
    Database& db, const std::vector<std::int64_t>& spared) {
  struct Running {
    std::int64_t id;
    WriterIdentity writer;
  };
  // First look without the write lock (every program start does this, and usually nothing is
  // running); the UPDATE below re-checks the status, so an attempt finished in between is
  // left alone.
  std::vector<Running> running;
  {
    DbResult<Statement> s = db.prepare(
        "SELECT id, writer_pid, writer_start, writer_host FROM attempts "
        "WHERE status = 'running' ORDER BY id");
    if (!s) return s.error();
    if (DbStatus r = s->for_each_row([&] {
          running.push_back(
              Running{s->column_int64(0),
                      WriterIdentity{s->column_int64(1), s->column_int64(2), s->column_text(3)}});
        });
        !r) {
      return r.error();
    }
  }

  const WriterIdentity self = current_writer();
  std::vector<Running> gone;
  for (const Running& r : running) {
    const bool is_self = r.writer.pid == self.pid && r.writer.host == self.host &&
                         r.writer.start_ticks == self.start_ticks;
    const bool is_spared = std::find(spared.begin(), spared.end(), r.id) != spared.end();
    if (!is_self && !is_spared && writer_state(r.writer) == WriterState::kGone) gone.push_back(r);
  }
  std::vector<std::int64_t> aborted;
  if (gone.empty()) return aborted;

  DbResult<Transaction> tx = Transaction::begin(db);
  if (!tx) return tx.error();
  // The end time is the last sign of life (begin or last checkpoint), not the time we noticed.
  DbResult<Statement> update = db.prepare(
      "UPDATE attempts SET status = 'aborted', ended_utc = heartbeat_utc, abort_reason = ? "
      "WHERE id = ? AND status = 'running'");
  if (!update) return update.error();
  for (const Running& r : gone) {
    const std::string reason = "the program recording it (pid " + std::to_string(r.writer.pid) +
                               " on " + r.writer.host + ") ended without finishing it";
    if (DbStatus b = update->bind_all(reason, r.id); !b) return b.error();
    if (DbStatus x = update->run(); !x) return x.error();
    if (db.changes() > 0) aborted.push_back(r.id);
    if (DbStatus x = update->reset(); !x) return x.error();
  }
  if (DbStatus c = tx->commit(); !c) return c.error();
  return aborted;
}

DbStatus update_attempt_assessment(Database& db, std::int64_t attempt_id, const Metrics& metrics,
                                   const ScoreResult& score) {
  DbResult<Transaction> tx = Transaction::begin(db);
  if (!tx) return tx.error();
  DbResult<AttemptStatus> status = read_status(db, attempt_id);
  if (!status) return status.error();
  if (status.value() != AttemptStatus::kCompleted) {
    return DbError{attempt_where(db, attempt_id) + "cannot re-score: it is " +
                       attempt_status_name(status.value()) + " (expected completed)",
                   0};
  }
  if (DbStatus w = write_assessment(db, attempt_id, metrics, score); !w) return w;
  DbResult<Statement> s = db.prepare("UPDATE attempts SET score = ?, passed = ? WHERE id = ?");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(score.score, score.passed, attempt_id); !b) return b;
  if (DbStatus r = s->run(); !r) return r;
  return tx->commit();
}

DbStatus update_aborted_metrics(Database& db, std::int64_t attempt_id, const Metrics& metrics) {
  DbResult<Transaction> tx = Transaction::begin(db);
  if (!tx) return tx.error();
  DbResult<AttemptStatus> status = read_status(db, attempt_id);
  if (!status) return status.error();
  if (status.value() != AttemptStatus::kAborted) {
    return DbError{attempt_where(db, attempt_id) + "cannot replace its metrics alone: it is " +
                       attempt_status_name(status.value()) + " (expected aborted)",
                   0};
  }
  // No score terms, gates or reasons, as a checkpoint stores them; score and passed stay NULL.
  if (DbStatus w = write_assessment(db, attempt_id, metrics, ScoreResult{}); !w) return w;
  return tx->commit();
}

DbResult<std::optional<AttemptRecord>> load_attempt(Database& db, std::int64_t attempt_id,
                                                    const AttemptDetail& detail) {
  // A read transaction: the row and its details come from one snapshot even while a writer
  // commits.
  DbResult<Transaction> tx = Transaction::begin(db, Transaction::Mode::kDeferred);
  if (!tx) return tx.error();
  DbResult<Statement> s =
      db.prepare(std::string("SELECT ") + kAttemptColumns + " FROM attempts WHERE id = ?");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(attempt_id); !b) return b.error();
  DbResult<bool> row = s->step();
  if (!row) return row.error();
  if (!row.value()) return std::optional<AttemptRecord>();
  AttemptRecord a = read_attempt_row(*s);
  if (DbStatus d = read_details(db, a, detail); !d) return d.error();
  if (DbStatus c = tx->commit(); !c) return c.error();
  return std::optional<AttemptRecord>(std::move(a));
}

DbResult<std::vector<AttemptRecord>> list_attempts(Database& db, const AttemptFilter& filter,
                                                   const AttemptDetail& detail) {
  DbResult<Transaction> tx = Transaction::begin(db, Transaction::Mode::kDeferred);
  if (!tx) return tx.error();
  DbResult<Statement> s = db.prepare(
      std::string("SELECT ") + kAttemptColumns +
      " FROM attempts WHERE (?1 IS NULL OR trainee_id = ?1) AND (?2 IS NULL OR module_id = ?2) "
      "AND (?3 OR trainee_id IS NOT NULL) ORDER BY started_utc, id");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(filter.trainee_id, filter.module_id, filter.include_practice); !b) {
    return b.error();
  }
  std::vector<AttemptRecord> out;
  if (DbStatus r = s->for_each_row([&] { out.push_back(read_attempt_row(*s)); }); !r) {
    return r.error();
  }
  for (AttemptRecord& a : out) {
    if (DbStatus d = read_details(db, a, detail); !d) return d.error();
  }
  if (DbStatus c = tx->commit(); !c) return c.error();
  return out;
}

}  // namespace acdr
