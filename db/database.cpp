// Opening the record file and running SQL on it: see database.hpp.
#include "db/database.hpp"

#include <pwd.h>
#include <sqlite3.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <thread>
#include <utility>

#include "db/schema.hpp"

namespace acdr {

namespace {

DbError open_error(const std::string& path, const std::string& what, sqlite3* db, int rc) {
  std::string message = path + ": " + what + ": ";
  message += db ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
  return DbError{std::move(message), rc};
}

// Reads one text value from a pragma that reports its new setting (journal_mode does).
DbResult<std::string> pragma_text(Database& db, std::string_view sql) {
  DbResult<Statement> stmt = db.prepare(sql);
  if (!stmt) return stmt.error();
  DbResult<bool> row = stmt->step();
  if (!row) return row.error();
  if (!row.value()) return std::string();
  return stmt->column_text(0);
}

}  // namespace

DbResult<Database> Database::open(const std::string& path, const OpenOptions& options) {
  namespace fs = std::filesystem;
  const bool in_memory = path == ":memory:" || path.empty();
  if (!in_memory && !options.create) {
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      return DbError{path + ": no record database here (expected an existing file; "
                            "check --db or $ACDR_DB)",
                     SQLITE_CANTOPEN};
    }
  }

  // Who the file belongs to is decided on a read-only connection first: switching to WAL (or
  // even rolling back another program's hot journal) would change a file we then refuse.
  std::error_code exists_ec;
  if (!in_memory && fs::exists(path, exists_ec)) {
    sqlite3* ro = nullptr;
    const int ro_rc = sqlite3_open_v2(path.c_str(), &ro, SQLITE_OPEN_READONLY, nullptr);
    if (ro_rc != SQLITE_OK) {
      DbError err = open_error(path, "cannot open the record database", ro, ro_rc);
      sqlite3_close_v2(ro);
      return err;
    }
    Database probe(ro, path);
    sqlite3_extended_result_codes(ro, 1);
    probe.set_busy_timeout_ms(options.busy_timeout_ms);
    if (DbStatus s = check_record_identity(probe, options.create && !options.read_only); !s)
      return s.error();
  }

  int flags = options.read_only ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE;
  if (options.create && !options.read_only) flags |= SQLITE_OPEN_CREATE;
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(in_memory ? ":memory:" : path.c_str(), &raw, flags, nullptr);
  if (rc != SQLITE_OK) {
    DbError err = open_error(path, "cannot open the record database", raw, rc);
    sqlite3_close_v2(raw);
    return err;
  }
  Database db(raw, in_memory ? std::string(":memory:") : path);
  sqlite3_extended_result_codes(raw, 1);

  // Wait for another process's lock instead of failing at once: a dashboard reads while an
  // attempt writes, and the attempt's commits are short.
  db.set_busy_timeout_ms(options.busy_timeout_ms);

  // Foreign keys are off by default in SQLite for backward compatibility; the record relies on
  // them (metrics cannot outlive their attempt).
  if (DbStatus s = db.exec("PRAGMA foreign_keys = ON"); !s) return s.error();

  if (!options.read_only) {
    // WAL: readers never block the writer and the writer never blocks readers; a process
    // killed mid-transaction leaves an uncommitted WAL tail that SQLite discards on next open.
    // Two programs opening a new record at once: the switch needs the file to itself, and
    // SQLite answers busy at once, without its busy handler, when waiting could deadlock (this
    // connection already reads the schema). Retried until the busy timeout.
    DbResult<std::string> mode = pragma_text(db, "PRAGMA journal_mode = WAL");
    for (int waited_ms = 0; !mode && (mode.error().sqlite_code & 0xff) == SQLITE_BUSY &&
                            waited_ms < options.busy_timeout_ms;
         waited_ms += 10) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      mode = pragma_text(db, "PRAGMA journal_mode = WAL");
    }
    if (!mode) return mode.error();
    if (mode.value() != "wal" && !(in_memory && mode.value() == "memory")) {
      return DbError{db.path() + ": cannot switch the record to WAL mode (journal_mode is '" +
                         mode.value() + "'; a network file system cannot host a WAL database)",
                     SQLITE_ERROR};
    }
    // FULL syncs the WAL at every commit: an attempt commits only a few times, and a record
    // that the user saw stored must survive a power cut.
    if (DbStatus s = db.exec("PRAGMA synchronous = FULL"); !s) return s.error();
    if (DbStatus s = migrate_schema(db); !s) return s.error();
  } else {
    if (DbStatus s = check_schema_current(db); !s) return s.error();
  }
  return db;
}

Database::Database(Database&& other) noexcept
    : db_(std::exchange(other.db_, nullptr)),
      path_(std::move(other.path_)),
      busy_timeout_ms_(other.busy_timeout_ms_) {}

Database& Database::operator=(Database&& other) noexcept {
  if (this != &other) {
    sqlite3_close_v2(db_);
    db_ = std::exchange(other.db_, nullptr);
    path_ = std::move(other.path_);
    busy_timeout_ms_ = other.busy_timeout_ms_;
  }
  return *this;
}

Database::~Database() {
  // close_v2 defers the close until every Statement is finalised, so destruction order between
  // a Database and its statements cannot leak or crash.
  sqlite3_close_v2(db_);
}

DbError Database::error(std::string_view what) const {
  std::string message = path_ + ": " + std::string(what) + ": " + sqlite3_errmsg(db_);
  return DbError{std::move(message), sqlite3_extended_errcode(db_)};
}

DbResult<Statement> Database::prepare(std::string_view sql) {
  sqlite3_stmt* stmt = nullptr;
  const char* tail = nullptr;
  const int rc = sqlite3_prepare_v3(db_, sql.data(), static_cast<int>(sql.size()), 0, &stmt,
                                    &tail);
  if (rc != SQLITE_OK) {
    DbError err = error("cannot prepare SQL (" + std::string(sql) + ")");
    sqlite3_finalize(stmt);
    return err;
  }
  return Statement(db_, stmt, path_);
}

DbStatus Database::exec(std::string_view sql) {
  // Prepare and run each statement of the script in turn (sqlite3_exec would do the same, but
  // this keeps "prepared statements only" literally true and errors in our format).
  const char* cursor = sql.data();
  const char* end = sql.data() + sql.size();
  while (cursor < end) {
    sqlite3_stmt* raw = nullptr;
    const char* tail = nullptr;
    const int rc = sqlite3_prepare_v3(db_, cursor, static_cast<int>(end - cursor), 0, &raw,
                                      &tail);
    if (rc != SQLITE_OK) {
      DbError err = error("cannot prepare SQL (" + std::string(cursor, end) + ")");
      sqlite3_finalize(raw);
      return err;
    }
    if (raw == nullptr) break;  // only whitespace or comments left
    Statement stmt(db_, raw, path_);
    if (DbStatus s = stmt.run(); !s) return s;
    cursor = tail;
  }
  return {};
}

DbResult<std::int64_t> Database::pragma_int(std::string_view name) {
  DbResult<Statement> stmt = prepare("PRAGMA " + std::string(name));
  if (!stmt) return stmt.error();
  DbResult<bool> row = stmt->step();
  if (!row) return row.error();
  if (!row.value()) return DbError{path_ + ": PRAGMA " + std::string(name) + " gave no value", 0};
  return stmt->column_int64(0);
}

void Database::set_busy_timeout_ms(int ms) {
  busy_timeout_ms_ = ms;
  sqlite3_busy_timeout(db_, ms);
}

std::int64_t Database::last_insert_rowid() const { return sqlite3_last_insert_rowid(db_); }

int Database::changes() const { return sqlite3_changes(db_); }

bool Database::in_transaction() const { return sqlite3_get_autocommit(db_) == 0; }

// ---- Transaction -------------------------------------------------------------------------

DbResult<Transaction> Transaction::begin(Database& db, Mode mode) {
  if (db.in_transaction()) {
    if (DbStatus s = db.exec("SAVEPOINT acdr_nested"); !s) return s.error();
    return Transaction(&db, true);
  }
  const char* sql = mode == Mode::kImmediate ? "BEGIN IMMEDIATE" : "BEGIN DEFERRED";
  if (DbStatus s = db.exec(sql); !s) return s.error();
  return Transaction(&db, false);
}

Transaction::Transaction(Transaction&& other) noexcept
    : db_(std::exchange(other.db_, nullptr)), savepoint_(other.savepoint_) {}

Transaction::~Transaction() { rollback(); }

DbStatus Transaction::commit() {
  if (db_ == nullptr) return DbError{"commit of a transaction that is no longer open", 0};
  DbStatus s = db_->exec(savepoint_ ? "RELEASE acdr_nested" : "COMMIT");
  if (s) db_ = nullptr;  // on failure the destructor still rolls back
  return s;
}

void Transaction::rollback() {
  if (db_ == nullptr) return;
  // SQLite may already have rolled back by itself after some errors (SQLITE_FULL, IOERR);
  // then there is nothing left to undo.
  if (db_->in_transaction()) {
    if (savepoint_) {
      (void)db_->exec("ROLLBACK TO acdr_nested");
      (void)db_->exec("RELEASE acdr_nested");
    } else {
      (void)db_->exec("ROLLBACK");
    }
  }
  db_ = nullptr;
}

// ---- default path ------------------------------------------------------------------------

std::string default_database_path() {
  namespace fs = std::filesystem;
  if (const char* env = std::getenv("ACDR_DB"); env && *env) return env;

  fs::path dir;
  // XDG Base Directory: a relative $XDG_DATA_HOME is invalid and must be ignored.
  if (const char* xdg = std::getenv("XDG_DATA_HOME"); xdg && *xdg && xdg[0] == '/') {
    dir = fs::path(xdg) / "acdr";
  } else {
    const char* home = std::getenv("HOME");
    if (!home || !*home) {
      const passwd* pw = getpwuid(getuid());
      home = pw ? pw->pw_dir : nullptr;
    }
    if (!home || !*home) return "acdr.sqlite";  // no home at all: the working directory
    dir = fs::path(home) / ".local" / "share" / "acdr";
  }
  std::error_code ec;
  if (!fs::exists(dir, ec)) {
    fs::create_directories(dir, ec);
    if (!ec) fs::permissions(dir, fs::perms::owner_all, fs::perm_options::replace, ec);
  }
  return (dir / "acdr.sqlite").string();
}

}  // namespace acdr
