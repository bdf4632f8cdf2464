// Tests of db/database.cpp: opening (WAL, foreign keys, schema stamp), refusing files we must
// not touch, transactions, concurrent readers and writers, and the default path.
#include "db/database.hpp"

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <stdlib.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#include "db/schema.hpp"
#include "tests/db/db_test_support.hpp"

namespace acdr {
namespace {

using test::TempDir;

// Sets raw pragmas/SQL on a file without going through Database (to fake other files).
void raw_exec(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* message = nullptr;
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message), SQLITE_OK)
      << (message ? message : "");
  sqlite3_free(message);
  sqlite3_close(db);
}

std::int64_t raw_pragma(const std::string& path, const std::string& name) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  sqlite3_stmt* stmt = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db, ("PRAGMA " + name).c_str(), -1, &stmt, nullptr), SQLITE_OK);
  std::int64_t value = -1;
  if (sqlite3_step(stmt) == SQLITE_ROW) value = sqlite3_column_int64(stmt, 0);
  sqlite3_finalize(stmt);
  sqlite3_close(db);
  return value;
}

DbResult<std::int64_t> count_trainees(Database& db) {
  DbResult<Statement> s = db.prepare("SELECT count(*) FROM trainees");
  if (!s) return s.error();
  DbResult<bool> row = s->step();
  if (!row) return row.error();
  return s->column_int64(0);
}

TEST(Database, OpenCreatesCurrentSchemaInWalWithForeignKeys) {
  TempDir dir;
  const std::string path = dir.file("record.sqlite");
  DbResult<Database> db = Database::open(path);
  ASSERT_TRUE(db.ok()) << db.error().message;
  EXPECT_TRUE(std::filesystem::exists(path));
  DbResult<Statement> mode = db->prepare("PRAGMA journal_mode");
  ASSERT_TRUE(mode.ok());
  ASSERT_TRUE(mode->step().value());
  EXPECT_EQ(mode->column_text(0), "wal");
  EXPECT_EQ(db->pragma_int("foreign_keys").value(), 1);
  EXPECT_EQ(db->pragma_int("user_version").value(), kSchemaVersion);
  EXPECT_EQ(db->pragma_int("application_id").value(), kApplicationId);
  EXPECT_EQ(db->pragma_int("synchronous").value(), 2);  // FULL
}

// Two replays started together record into one new file (scripts/demonstrations runs two
// at a time): every opener gets the record, none "database is locked". Switching a new file
// to WAL answered busy at once to one of them (SQLite skips its busy handler where waiting
// could deadlock), and that replay failed. And the check of whose file it is read the version
// and the tables one by one: an opener whose neighbour committed the new record in between
// found tables without a version and refused the file as someone else's (1 run in 40 of this
// test on a loaded host; read in one transaction, 0 in 180).
TEST(Database, ProgramsOpeningANewRecordAtOnceAllGetIt) {
  for (int round = 0; round < 20; ++round) {
    TempDir dir;
    const std::string path = dir.file("record.sqlite");
    constexpr int kOpeners = 6;
    std::atomic<int> ready{0};
    std::atomic<int> opened{0};
    std::vector<std::string> errors(kOpeners);
    std::vector<std::thread> threads;
    for (int t = 0; t < kOpeners; ++t)
      threads.emplace_back([&, t] {
        ++ready;
        while (ready.load() < kOpeners) std::this_thread::yield();
        DbResult<Database> db = Database::open(path);
        if (db.ok()) ++opened;
        else errors[t] = db.error().message;
      });
    for (auto& th : threads) th.join();
    for (const auto& e : errors) EXPECT_EQ(e, "") << "round " << round;
    ASSERT_EQ(opened.load(), kOpeners) << "round " << round;
  }
}

TEST(Database, ReopeningIsIdempotentAndKeepsData) {
  TempDir dir;
  const std::string path = dir.file("record.sqlite");
  {
    Database db = test::open_or_fail(path);
    ASSERT_TRUE(upsert_trainee(db, TraineeRecord{"t1", "One", ""}).ok());
  }
  Database db = test::open_or_fail(path);
  EXPECT_EQ(count_trainees(db).value(), 1);
  EXPECT_EQ(db.pragma_int("user_version").value(), kSchemaVersion);
}

TEST(Database, MissingFileWithoutCreateIsAnErrorNamingThePath) {
  TempDir dir;
  const std::string path = dir.file("typo.sqlite");
  OpenOptions options;
  options.create = false;
  DbResult<Database> db = Database::open(path, options);
  ASSERT_FALSE(db.ok());
  EXPECT_NE(db.error().message.find(path), std::string::npos) << db.error().message;
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(Database, RefusesANewerSchemaAndLeavesTheFileAlone) {
  TempDir dir;
  const std::string path = dir.file("future.sqlite");
  { ASSERT_TRUE(Database::open(path).ok()); }
  raw_exec(path, "PRAGMA user_version = " + std::to_string(kSchemaVersion + 1));

  DbResult<Database> db = Database::open(path);
  ASSERT_FALSE(db.ok());
  const std::string& message = db.error().message;
  EXPECT_NE(message.find("newer"), std::string::npos) << message;
  EXPECT_NE(message.find(std::to_string(kSchemaVersion + 1)), std::string::npos) << message;
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_EQ(raw_pragma(path, "user_version"), kSchemaVersion + 1);

  OpenOptions read_only;
  read_only.read_only = true;
  EXPECT_FALSE(Database::open(path, read_only).ok());
}

TEST(Database, RefusesAnotherProgramsDatabase) {
  TempDir dir;
  const std::string tables = dir.file("other.sqlite");
  raw_exec(tables, "CREATE TABLE notes (body TEXT)");
  DbResult<Database> a = Database::open(tables);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.error().message.find("not an ACDR record"), std::string::npos);
  EXPECT_EQ(raw_pragma(tables, "user_version"), 0);

  const std::string stamped = dir.file("stamped.sqlite");
  raw_exec(stamped, "PRAGMA application_id = 1234");
  DbResult<Database> b = Database::open(stamped);
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.error().message.find("1234"), std::string::npos) << b.error().message;
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Refusing is decided on a read-only connection, before any pragma that writes: the header
// (journal mode bytes 18-19, the change counter) and every page stay exactly as they were.
TEST(Database, RefusedFilesAreLeftByteForByteUnchanged) {
  TempDir dir;
  const std::string tables = dir.file("notes.sqlite");
  raw_exec(tables, "CREATE TABLE notes (x); INSERT INTO notes VALUES (1)");
  const std::string stamped = dir.file("stamped.sqlite");
  raw_exec(stamped, "PRAGMA application_id = 1234; CREATE TABLE t (x)");
  const std::string newer = dir.file("newer.sqlite");
  raw_exec(newer, "PRAGMA user_version = " + std::to_string(kSchemaVersion + 1));
  for (const std::string& path : {tables, stamped, newer}) {
    const std::string before = file_bytes(path);
    ASSERT_FALSE(before.empty());
    for (bool create : {true, false}) {
      OpenOptions options;
      options.create = create;
      DbResult<Database> db = Database::open(path, options);
      ASSERT_FALSE(db.ok()) << path;
      EXPECT_NE(db.error().message.find("not changed"), std::string::npos)
          << db.error().message;
      EXPECT_EQ(file_bytes(path), before) << path << " (create " << create << ")";
      EXPECT_FALSE(std::filesystem::exists(path + "-wal")) << path;
    }
  }
}

// A command that only reads (create = false) does not start a record in an empty file; one
// that writes (create = true, `acdr run`) does.
TEST(Database, AnEmptyFileIsInitialisedOnlyWhenCreating) {
  TempDir dir;
  const std::string path = dir.file("empty.sqlite");
  { std::ofstream touch(path); }
  OpenOptions reader;
  reader.create = false;
  DbResult<Database> refused = Database::open(path, reader);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().message.find("an empty file"), std::string::npos)
      << refused.error().message;
  EXPECT_EQ(std::filesystem::file_size(path), 0u);

  {
    DbResult<Database> created = Database::open(path);
    ASSERT_TRUE(created.ok()) << created.error().message;
    EXPECT_EQ(created->pragma_int("user_version").value(), kSchemaVersion);
  }
  EXPECT_TRUE(Database::open(path, reader).ok());
}

TEST(Database, ReadOnlyOpenNeedsACurrentRecord) {
  TempDir dir;
  const std::string path = dir.file("record.sqlite");
  { ASSERT_TRUE(Database::open(path).ok()); }
  OpenOptions read_only;
  read_only.read_only = true;
  DbResult<Database> db = Database::open(path, read_only);
  ASSERT_TRUE(db.ok()) << db.error().message;
  EXPECT_FALSE(upsert_trainee(db.value(), TraineeRecord{"t1", "", ""}).ok());

  const std::string empty = dir.file("empty.sqlite");
  raw_exec(empty, "PRAGMA user_version = 0");
  EXPECT_FALSE(Database::open(empty, read_only).ok());
}

TEST(Database, TransactionRollsBackUnlessCommitted) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  {
    DbResult<Transaction> tx = Transaction::begin(db);
    ASSERT_TRUE(tx.ok());
    ASSERT_TRUE(upsert_trainee(db, TraineeRecord{"lost", "", ""}).ok());
  }
  EXPECT_EQ(count_trainees(db).value(), 0);
  EXPECT_FALSE(db.in_transaction());
  {
    DbResult<Transaction> tx = Transaction::begin(db);
    ASSERT_TRUE(upsert_trainee(db, TraineeRecord{"kept", "", ""}).ok());
    ASSERT_TRUE(tx->commit().ok());
  }
  EXPECT_EQ(count_trainees(db).value(), 1);
}

TEST(Database, NestedTransactionIsASavepoint) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  DbResult<Transaction> outer = Transaction::begin(db);
  ASSERT_TRUE(outer.ok());
  ASSERT_TRUE(upsert_trainee(db, TraineeRecord{"outer", "", ""}).ok());
  {
    DbResult<Transaction> inner = Transaction::begin(db);
    ASSERT_TRUE(inner.ok());
    ASSERT_TRUE(upsert_trainee(db, TraineeRecord{"inner", "", ""}).ok());
    // not committed: only the inner part is undone
  }
  EXPECT_TRUE(db.in_transaction());
  ASSERT_TRUE(outer->commit().ok());
  EXPECT_EQ(count_trainees(db).value(), 1);
  EXPECT_TRUE(find_trainee(db, "outer").value().has_value());
}

TEST(Database, ReaderIsNotBlockedWhileAWriterHoldsATransaction) {
  TempDir dir;
  const std::string path = dir.file("record.sqlite");
  Database writer = test::open_or_fail(path);
  ASSERT_TRUE(upsert_trainee(writer, TraineeRecord{"t0", "", ""}).ok());

  OpenOptions short_wait;
  short_wait.busy_timeout_ms = 100;
  Database reader = test::open_or_fail(path, short_wait);

  DbResult<Transaction> tx = Transaction::begin(writer);
  ASSERT_TRUE(tx.ok());
  ASSERT_TRUE(upsert_trainee(writer, TraineeRecord{"t1", "", ""}).ok());

  // WAL: the reader sees the last committed state at once, without waiting for the lock.
  const auto t0 = std::chrono::steady_clock::now();
  DbResult<std::int64_t> before = count_trainees(reader);
  const auto waited = std::chrono::steady_clock::now() - t0;
  ASSERT_TRUE(before.ok()) << before.error().message;
  EXPECT_EQ(before.value(), 1);
  EXPECT_LT(waited, std::chrono::milliseconds(50));

  // A second writer waits its busy timeout, then gets an error (not a crash, not a hang).
  Database second = test::open_or_fail(path, short_wait);
  DbStatus blocked = upsert_trainee(second, TraineeRecord{"t2", "", ""});
  ASSERT_FALSE(blocked.ok());
  EXPECT_EQ(blocked.error().sqlite_code & 0xFF, SQLITE_BUSY) << blocked.error().message;

  ASSERT_TRUE(tx->commit().ok());
  EXPECT_EQ(count_trainees(reader).value(), 2);
  EXPECT_TRUE(upsert_trainee(second, TraineeRecord{"t2", "", ""}).ok());
}

TEST(Database, DashboardReadsWhileAttemptsAreWritten) {
  TempDir dir;
  const std::string path = dir.file("record.sqlite");
  {
    Database db = test::open_or_fail(path);
    test::register_curriculum(db, 1);
  }
  constexpr int kAttempts = 30;
  std::atomic<bool> writing{true};
  std::atomic<int> read_errors{0};
  std::atomic<int> reads{0};
  std::string first_error;

  std::thread reader([&] {
    Database db = test::open_or_fail(path);
    std::size_t last_seen = 0;
    while (writing.load()) {
      DbResult<std::vector<AttemptRecord>> attempts = list_attempts(db);
      if (!attempts) {
        if (read_errors++ == 0) first_error = attempts.error().message;
        continue;
      }
      // A snapshot never goes backwards and never shows a half-finished attempt.
      if (attempts->size() < last_seen) ++read_errors;
      last_seen = attempts->size();
      for (const AttemptRecord& a : attempts.value()) {
        if (a.status == AttemptStatus::kCompleted && a.metrics.values.size() != 2) ++read_errors;
      }
      ++reads;
    }
  });

  Database db = test::open_or_fail(path);
  for (int i = 0; i < kAttempts; ++i) {
    test::add_attempt(db, "t1", "m1", 60.0, true, test::minute(i % 60));
  }
  writing = false;
  reader.join();
  EXPECT_EQ(read_errors.load(), 0) << first_error;
  EXPECT_GT(reads.load(), 0);
  EXPECT_EQ(list_attempts(db).value().size(), static_cast<std::size_t>(kAttempts));
}

// Environment variables are process-wide: restore them whatever the test does.
class ScopedEnv {
 public:
  explicit ScopedEnv(const char* name) : name_(name) {
    if (const char* v = std::getenv(name)) old_ = v;
  }
  ~ScopedEnv() {
    if (old_) {
      setenv(name_, old_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }
  void set(const std::string& value) { setenv(name_, value.c_str(), 1); }
  void unset() { unsetenv(name_); }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

TEST(Database, DefaultPathFollowsAcdrDbThenXdgThenHome) {
  TempDir dir;
  ScopedEnv acdr_db("ACDR_DB"), xdg("XDG_DATA_HOME"), home("HOME");

  acdr_db.set(dir.file("explicit.sqlite"));
  EXPECT_EQ(default_database_path(), dir.file("explicit.sqlite"));

  acdr_db.unset();
  xdg.set(dir.file("xdg"));
  EXPECT_EQ(default_database_path(), dir.file("xdg") + "/acdr/acdr.sqlite");
  EXPECT_TRUE(std::filesystem::is_directory(dir.file("xdg") + "/acdr"));

  xdg.set("relative/path");  // invalid per the XDG spec: ignored
  home.set(dir.file("home"));
  EXPECT_EQ(default_database_path(), dir.file("home") + "/.local/share/acdr/acdr.sqlite");
  EXPECT_TRUE(std::filesystem::is_directory(dir.file("home") + "/.local/share/acdr"));

  xdg.unset();
  DbResult<Database> db = Database::open(default_database_path());
  EXPECT_TRUE(db.ok()) << db.error().message;
}

TEST(Database, HostileTextIsBoundNotExecutedAndStoredVerbatim) {
  TempDir dir;
  Database db = test::open_or_fail(dir.file("record.sqlite"));
  const std::vector<std::string> hostile = {
      "Robert'); DROP TABLE attempts;--",
      "a\"b'c;d",
      "'; DELETE FROM trainees WHERE '1'='1",
      std::string("nul\0inside", 10),
      "line\nbreak\r\nand\ttab",
      "\xC3\xA9l\xC3\xA8ve \xE2\x9C\x93",
      "%s%n %x"};
  for (std::size_t i = 0; i < hostile.size(); ++i) {
    ASSERT_TRUE(
        upsert_trainee(db, TraineeRecord{hostile[i], hostile[(i + 1) % hostile.size()], ""}).ok());
  }
  for (std::size_t i = 0; i < hostile.size(); ++i) {
    DbResult<std::optional<TraineeRecord>> t = find_trainee(db, hostile[i]);
    ASSERT_TRUE(t.ok());
    ASSERT_TRUE(t.value().has_value()) << "missing: " << hostile[i];
    EXPECT_EQ(t.value()->id, hostile[i]);
    EXPECT_EQ(t.value()->display_name, hostile[(i + 1) % hostile.size()]);
  }
  EXPECT_EQ(count_trainees(db).value(), static_cast<std::int64_t>(hostile.size()));
  // The tables the injections aimed at are still there.
  test::register_curriculum(db, 1);
  EXPECT_NE(test::add_attempt(db, hostile[0], "m1", 70.0, true, test::minute(1)), 0);
}

}  // namespace
}  // namespace acdr
