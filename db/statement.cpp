// Prepared statement wrapper: see statement.hpp.
#include "db/statement.hpp"

#include <sqlite3.h>

#include <utility>

namespace acdr {

Statement::Statement(sqlite3* db, sqlite3_stmt* stmt, std::string db_path)
    : db_(db), stmt_(stmt), db_path_(std::move(db_path)) {}

Statement::Statement(Statement&& other) noexcept
    : db_(std::exchange(other.db_, nullptr)),
      stmt_(std::exchange(other.stmt_, nullptr)),
      db_path_(std::move(other.db_path_)) {}

Statement& Statement::operator=(Statement&& other) noexcept {
  if (this != &other) {
    sqlite3_finalize(stmt_);
    db_ = std::exchange(other.db_, nullptr);
    stmt_ = std::exchange(other.stmt_, nullptr);
    db_path_ = std::move(other.db_path_);
  }
  return *this;
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

std::string Statement::sql() const {
  const char* text = stmt_ ? sqlite3_sql(stmt_) : nullptr;
  return text ? text : "";
}

DbError Statement::error(const char* what, int code) const {
  std::string message = db_path_ + ": " + what + " failed: ";
  message += (db_ && sqlite3_extended_errcode(db_) == code) ? sqlite3_errmsg(db_)
                                                             : sqlite3_errstr(code);
  message += " (SQL: " + sql() + ")";
  return DbError{std::move(message), code};
}

DbStatus Statement::bind_null(int index) {
  const int rc = sqlite3_bind_null(stmt_, index);
  if (rc != SQLITE_OK) return error("bind", rc);
  return {};
}

DbStatus Statement::bind_int64(int index, std::int64_t value) {
  const int rc = sqlite3_bind_int64(stmt_, index, value);
  if (rc != SQLITE_OK) return error("bind", rc);
  return {};
}

DbStatus Statement::bind_double(int index, double value) {
  const int rc = sqlite3_bind_double(stmt_, index, value);
  if (rc != SQLITE_OK) return error("bind", rc);
  return {};
}

DbStatus Statement::bind_text(int index, std::string_view value) {
  // SQLITE_TRANSIENT: SQLite copies the text, so temporaries are safe to bind.
  const int rc = sqlite3_bind_text64(stmt_, index, value.data(), value.size(), SQLITE_TRANSIENT,
                                     SQLITE_UTF8);
  if (rc != SQLITE_OK) return error("bind", rc);
  return {};
}

DbStatus Statement::bind_blob(int index, BlobView value) {
  // A zero-length blob is still a blob, not NULL: bind an empty one explicitly.
  const int rc = value.empty()
                     ? sqlite3_bind_zeroblob(stmt_, index, 0)
                     : sqlite3_bind_blob64(stmt_, index, value.data(), value.size(),
                                           SQLITE_TRANSIENT);
  if (rc != SQLITE_OK) return error("bind", rc);
  return {};
}

DbResult<bool> Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  // Reset so the statement can be reused and the error does not stick to the connection.
  DbError err = error("step", sqlite3_extended_errcode(db_));
  sqlite3_reset(stmt_);
  return err;
}

DbStatus Statement::run() {
  return for_each_row([] {});
}

DbStatus Statement::reset() {
  const int rc = sqlite3_reset(stmt_);
  if (rc != SQLITE_OK) return error("reset", rc);
  return {};
}

bool Statement::column_is_null(int column) const {
  return sqlite3_column_type(stmt_, column) == SQLITE_NULL;
}

std::int64_t Statement::column_int64(int column) const {
  return sqlite3_column_int64(stmt_, column);
}

double Statement::column_double(int column) const { return sqlite3_column_double(stmt_, column); }

std::string Statement::column_text(int column) const {
  // Read the pointer first, then the size (SQLite's documented order for conversions).
  const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, column));
  const int size = sqlite3_column_bytes(stmt_, column);
  return text ? std::string(text, static_cast<std::size_t>(size)) : std::string();
}

std::vector<std::uint8_t> Statement::column_blob(int column) const {
  const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(stmt_, column));
  const int size = sqlite3_column_bytes(stmt_, column);
  if (!data || size <= 0) return {};
  return std::vector<std::uint8_t>(data, data + size);
}

std::optional<std::int64_t> Statement::column_optional_int64(int column) const {
  if (column_is_null(column)) return std::nullopt;
  return column_int64(column);
}

std::optional<double> Statement::column_optional_double(int column) const {
  if (column_is_null(column)) return std::nullopt;
  return column_double(column);
}

std::optional<std::string> Statement::column_optional_text(int column) const {
  if (column_is_null(column)) return std::nullopt;
  return column_text(column);
}

}  // namespace acdr
