// Tests of db/schema.cpp: migrations are ordered and complete, and the schema enforces what
// the store relies on (foreign keys, allowed statuses, cascades).
#include "db/schema.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>

#include "db/attempt_store.hpp"
#include "db/database.hpp"
#include "tests/db/db_test_support.hpp"

namespace acdr {
namespace {

/// Writes a record of schema `version` (its first `version` migrations, stamped as ours) with
/// the rows of `rows_sql`, as an older acdr left it: run on a new file at `path`, outside
/// Database.
void write_old_record(const std::string& path, int version, const std::string& rows_sql) {
  std::string sql;
  for (int v = 0; v < version; ++v) sql += schema_migrations()[v].sql;
  sql += "PRAGMA user_version = " + std::to_string(version) +
         "; PRAGMA application_id = " + std::to_string(kApplicationId) + ";" + rows_sql;
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &raw), SQLITE_OK);
  char* message = nullptr;
  const int rc = sqlite3_exec(raw, sql.c_str(), nullptr, nullptr, &message);
  const std::string error = message ? message : "";
  sqlite3_free(message);
  sqlite3_close(raw);
  ASSERT_EQ(rc, SQLITE_OK) << error;
}

TEST(Schema, MigrationsAreOrderedOnePerVersion) {
  const auto migrations = schema_migrations();
  ASSERT_EQ(static_cast<int>(migrations.size()), kSchemaVersion);
  for (std::size_t i = 0; i < migrations.size(); ++i) {
    EXPECT_EQ(migrations[i].version, static_cast<int>(i) + 1);
    EXPECT_NE(std::string(migrations[i].description), "");
  }
}

TEST(Schema, EveryEntityHasItsTable) {
  test::TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  for (const char* table : {"trainees", "curricula", "modules", "module_prerequisites",
                            "attempts", "metrics", "events", "recordings", "score_terms",
                            "score_gates", "score_reasons", "recording_chunks",
                            "xapi_outbox"}) {
    DbResult<Statement> s = db.prepare("SELECT count(*) FROM sqlite_schema WHERE name = ?");
    ASSERT_TRUE(s->bind_all(table).ok());
    ASSERT_TRUE(s->step().value());
    EXPECT_EQ(s->column_int64(0), 1) << table;
  }
}

TEST(Schema, ConstraintsHold) {
  test::TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  test::register_curriculum(db, 1);
  // Foreign keys: no metric without its attempt, no attempt at an unknown module.
  EXPECT_FALSE(db.exec("INSERT INTO metrics (attempt_id, name, position, value) "
                       "VALUES (42, 'x', 0, 1.0)")
                   .ok());
  EXPECT_FALSE(db.exec("INSERT INTO attempts (uuid, registration, module_id, started_utc, "
                       "heartbeat_utc, writer_pid, writer_host) "
                       "VALUES ('u', 'r', 'nope', 't', 't', 1, 'h')")
                   .ok());
  // Only the three statuses; a completed attempt must have an end and a pass decision.
  EXPECT_FALSE(db.exec("INSERT INTO attempts (uuid, registration, module_id, status, "
                       "started_utc, heartbeat_utc, writer_pid, writer_host) "
                       "VALUES ('u', 'r', 'm1', 'paused', 't', 't', 1, 'h')")
                   .ok());
  EXPECT_FALSE(db.exec("INSERT INTO attempts (uuid, registration, module_id, status, "
                       "started_utc, heartbeat_utc, writer_pid, writer_host) "
                       "VALUES ('u', 'r', 'm1', 'completed', 't', 't', 1, 'h')")
                   .ok());
  // STRICT: a text where a number belongs is refused, not converted.
  EXPECT_FALSE(db.exec("UPDATE modules SET position = 'first' WHERE id = 'm1'").ok());
  EXPECT_FALSE(db.exec("UPDATE modules SET pass_score = x'00' WHERE id = 'm1'").ok());

  // Deleting an attempt takes its children with it.
  const std::int64_t id = test::add_attempt(db, "t1", "m1", 60, true, test::minute(0));
  DbResult<Statement> del = db.prepare("DELETE FROM attempts WHERE id = ?");
  ASSERT_TRUE(del->bind_all(id).ok());
  ASSERT_TRUE(del->run().ok());
  DbResult<Statement> left = db.prepare(
      "SELECT (SELECT count(*) FROM metrics) + (SELECT count(*) FROM events) + "
      "(SELECT count(*) FROM score_terms)");
  ASSERT_TRUE(left->step().value());
  EXPECT_EQ(left->column_int64(0), 0);
}

// A record written by a v1 program (events with '' for "no zone") is upgraded in place when a
// v2 program opens it: '' becomes NULL, zone names stay, recording_chunks appears.
TEST(Schema, MigratesAVersion1RecordKeepingItsEvents) {
  test::TempDir dir;
  const std::string path = dir.file("v1.sqlite");
  {
    const std::string sql =
        "INSERT INTO modules (id) VALUES ('m1');"
        "INSERT INTO attempts (uuid, registration, module_id, started_utc, heartbeat_utc, "
        "  writer_pid, writer_host) VALUES ('u1', 'r1', 'm1', 't', 't', 1, 'h');"
        "INSERT INTO events (attempt_id, seq, t_s, kind, zone, value) VALUES "
        "  (1, 0, 0.5, 'zone_warning', 'foramen_left', 1.5), (1, 1, 0.7, 'overload_warning', '', 0.3);";
    ASSERT_NO_FATAL_FAILURE(write_old_record(path, 1, sql));
  }
  Database db = test::open_or_fail(path);
  EXPECT_EQ(db.pragma_int("user_version").value(), kSchemaVersion);
  DbResult<Statement> s = db.prepare(
      "SELECT kind, zone, zone_index FROM events WHERE attempt_id = 1 ORDER BY seq");
  ASSERT_TRUE(s.ok());
  ASSERT_TRUE(s->step().value());
  EXPECT_EQ(s->column_optional_text(1), std::optional<std::string>("foramen_left"));
  EXPECT_TRUE(s->column_is_null(2));
  ASSERT_TRUE(s->step().value());
  EXPECT_EQ(s->column_text(0), "overload_warning");
  EXPECT_TRUE(s->column_is_null(1));
  EXPECT_FALSE(s->step().value());
  // '' is no longer a zone name the table accepts: "no zone" has one spelling.
  EXPECT_FALSE(db.exec("INSERT INTO events (attempt_id, seq, kind, zone) VALUES (1, 2, 'x', '')").ok());
  EXPECT_TRUE(db.exec("SELECT count(*) FROM recording_chunks").ok());
  EXPECT_TRUE(db.exec("SELECT count(*) FROM xapi_outbox").ok());  // v3, in the same opening
}

// A version 3 record (before the real-time factor was kept) opens with its attempts readable:
// the factor of an old attempt is unknown (NULL), a new attempt stores its own, and the column
// refuses a factor that cannot be one.
TEST(Schema, MigratesAVersion3RecordAddingTheRealTimeFactor) {
  test::TempDir dir;
  const std::string path = dir.file("v3.sqlite");
  {
    const std::string sql =
        "INSERT INTO trainees (id, created_utc) VALUES ('t1', '2024-05-01T09:00:00.000Z');"
        "INSERT INTO modules (id) VALUES ('m1');"
        "INSERT INTO attempts (uuid, registration, trainee_id, module_id, status, "
        "  started_utc, ended_utc, heartbeat_utc, duration_s, score, passed, writer_pid, "
        "  writer_host) VALUES ('u1', 'r1', 't1', 'm1', 'completed', "
        "  '2024-05-01T09:00:00.000Z', '2024-05-01T09:01:00.000Z', "
        "  '2024-05-01T09:01:00.000Z', 60.0, 72.5, 1, 1, 'h');";
    ASSERT_NO_FATAL_FAILURE(write_old_record(path, 3, sql));
  }
  Database db = test::open_or_fail(path);
  EXPECT_EQ(db.pragma_int("user_version").value(), kSchemaVersion);
  DbResult<std::vector<AttemptRecord>> old = list_attempts(db, {});
  ASSERT_TRUE(old.ok()) << old.error().message;
  ASSERT_EQ(old->size(), 1u);
  EXPECT_EQ(old->front().score, 72.5);
  EXPECT_EQ(old->front().duration_s, 60.0);
  EXPECT_FALSE(old->front().realtime_factor.has_value());

  test::register_curriculum(db, 1);
  const std::int64_t id = test::add_attempt(db, "t1", "m1", 60, true, test::minute(5));
  DbResult<std::optional<AttemptRecord>> fresh = load_attempt(db, id);
  ASSERT_TRUE(fresh.ok() && fresh.value());
  EXPECT_EQ(fresh.value()->realtime_factor, test::make_outcome(60, true).realtime_factor);
  EXPECT_FALSE(db.exec("UPDATE attempts SET realtime_factor = 0 WHERE id = 1").ok());
  EXPECT_FALSE(db.exec("UPDATE attempts SET realtime_factor = -0.5 WHERE id = 1").ok());
}

}  // namespace
}  // namespace acdr
