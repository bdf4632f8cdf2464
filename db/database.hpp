// The connection to the training-record file: opening (WAL, foreign keys, busy timeout, schema
// migration), prepared statements and transactions. One Database per thread; many processes may
// open the same file (a dashboard reads while an attempt writes).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "db/db_result.hpp"
#include "db/statement.hpp"

struct sqlite3;

namespace acdr {

/// How to open the record file.
struct OpenOptions {
  /// Create the file (and run every migration) when it does not exist or is empty (0 bytes,
  /// or SQLite without tables). false: a missing or empty file is an error, left unchanged, so
  /// a typo in --db, or a command that only reads, does not silently start an empty record.
  bool create = true;
  /// Open read-only: no migration, no WAL switch; the schema must already be current.
  bool read_only = false;
  /// How long a statement waits for another connection's lock before failing (ms). A running
  /// attempt commits in a few ms, so 5 s is generous.
  int busy_timeout_ms = 5000;
};

class Database {
 public:
  /// Opens (or creates) the SQLite file at `path`, switches it to WAL, turns foreign keys on,
  /// sets the busy timeout and brings the schema to the version this program knows
  /// (schema.hpp). Refuses a file whose schema is newer than that, or that is not an ACDR
  /// record. Errors name the path.
  static DbResult<Database> open(const std::string& path, const OpenOptions& options = {});

  Database() = default;
  Database(Database&& other) noexcept;
  Database& operator=(Database&& other) noexcept;
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;
  ~Database();

  /// Prepares one SQL statement. The SQL must be a constant of the program; values go through
  /// Statement::bind.
  DbResult<Statement> prepare(std::string_view sql);
  /// Runs constant SQL without parameters (one or more statements), e.g. a migration script.
  DbStatus exec(std::string_view sql);
  /// Reads an integer pragma such as "user_version" (constant names only).
  DbResult<std::int64_t> pragma_int(std::string_view name);

  /// How long a statement waits for another connection's lock (OpenOptions::busy_timeout_ms
  /// until changed).
  int busy_timeout_ms() const { return busy_timeout_ms_; }
  void set_busy_timeout_ms(int ms);

  std::int64_t last_insert_rowid() const;
  /// Rows changed by the last INSERT/UPDATE/DELETE on this connection.
  int changes() const;
  /// True while a transaction is open on this connection.
  bool in_transaction() const;
  const std::string& path() const { return path_; }
  sqlite3* handle() const { return db_; }

  /// An error in the house format: "<path>: <what>: <sqlite message>".
  DbError error(std::string_view what) const;

 private:
  Database(sqlite3* db, std::string path) : db_(db), path_(std::move(path)) {}

  sqlite3* db_ = nullptr;
  std::string path_;
  int busy_timeout_ms_ = 0;
};

/// A transaction that rolls back unless committed. Inside another transaction it becomes a
/// SAVEPOINT, so store functions can be composed into one caller transaction.
class [[nodiscard]] Transaction {
 public:
  enum class Mode {
    kDeferred,   ///< read transaction (a consistent snapshot for reports)
    kImmediate,  ///< takes the write lock at once (every write: avoids a BUSY lock upgrade)
  };

  static DbResult<Transaction> begin(Database& db, Mode mode = Mode::kImmediate);

  Transaction(Transaction&& other) noexcept;
  Transaction& operator=(Transaction&&) = delete;
  Transaction(const Transaction&) = delete;
  ~Transaction();

  DbStatus commit();
  /// Undoes everything since begin(); also done by the destructor when not committed.
  void rollback();

 private:
  Transaction(Database* db, bool savepoint) : db_(db), savepoint_(savepoint) {}

  Database* db_ = nullptr;
  bool savepoint_ = false;
};

/// Where the record lives when --db is not given: $ACDR_DB if set and non-empty, else
/// $XDG_DATA_HOME/acdr/acdr.sqlite, else ~/.local/share/acdr/acdr.sqlite (XDG Base Directory
/// default). Creates the parent directory (0700) when missing; if that fails the path is still
/// returned and opening it reports the problem.
std::string default_database_path();

/// Sets a connection's busy timeout for a scope and puts the previous one back at its end.
class ScopedBusyTimeout {
 public:
  ScopedBusyTimeout(Database& db, int ms) : db_(db), previous_ms_(db.busy_timeout_ms()) {
    db_.set_busy_timeout_ms(ms);
  }
  ~ScopedBusyTimeout() { db_.set_busy_timeout_ms(previous_ms_); }
  ScopedBusyTimeout(const ScopedBusyTimeout&) = delete;
  ScopedBusyTimeout& operator=(const ScopedBusyTimeout&) = delete;

 private:
  Database& db_;
  int previous_ms_;
};

}  // namespace acdr
