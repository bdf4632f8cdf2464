// A prepared SQLite statement owned by RAII: bind parameters by position, step through rows,
// read columns. Every value from outside the program reaches SQL only through bind(), never by
// building SQL text (docs/architecture.md, SQLite).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "db/db_result.hpp"

struct sqlite3;
struct sqlite3_stmt;

namespace acdr {

/// Bytes bound as a BLOB parameter.
using BlobView = std::span<const std::uint8_t>;

class Statement {
 public:
  Statement() = default;
  /// Takes ownership of `stmt` (from sqlite3_prepare_v3 on `db`).
  Statement(sqlite3* db, sqlite3_stmt* stmt, std::string db_path);
  Statement(Statement&& other) noexcept;
  Statement& operator=(Statement&& other) noexcept;
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  ~Statement();

  /// Binds one parameter, 1-based like SQLite. Accepts integers, bool (0/1), floating point,
  /// text (anything convertible to std::string_view; copied), BlobView, nullptr (NULL), and
  /// std::optional of these (nullopt binds NULL).
  template <class T>
  DbStatus bind(int index, const T& value);

  /// Binds all parameters in order, starting at 1.
  template <class... Args>
  DbStatus bind_all(const Args&... args) {
    int index = 0;
    DbStatus status;
    ((status = status.ok() ? bind(++index, args) : status), ...);
    return status;
  }

  /// Advances to the next row. true: a row is ready to read; false: the statement is done.
  DbResult<bool> step();
  /// Steps until done, ignoring any rows (for INSERT/UPDATE/DELETE and pragmas that set).
  DbStatus run();
  /// Makes the statement ready to run again; bindings are kept until rebound.
  DbStatus reset();

  /// Steps through every row, calling `on_row()` to read each one's columns. Stops at the first
  /// error, SQLite's or `on_row`'s when it returns a DbStatus.
  template <class OnRow>
  DbStatus for_each_row(OnRow on_row);

  /// Runs the statement once per element of `items`: `bind_item(i, items[i])` binds its
  /// parameters (returning the DbStatus of bind_all), then the statement runs and is reset.
  /// An error from running row i is returned with `row_name(i)` and ": " before its message.
  template <class Items, class BindItem, class RowName>
  DbStatus run_for_each(const Items& items, BindItem bind_item, RowName row_name);

  bool column_is_null(int column) const;  ///< 0-based, like SQLite
  std::int64_t column_int64(int column) const;
  double column_double(int column) const;
  std::string column_text(int column) const;
  std::vector<std::uint8_t> column_blob(int column) const;
  std::optional<std::int64_t> column_optional_int64(int column) const;
  std::optional<double> column_optional_double(int column) const;
  std::optional<std::string> column_optional_text(int column) const;

  /// The SQL text, for error messages.
  std::string sql() const;
  bool valid() const { return stmt_ != nullptr; }

 private:
  DbStatus bind_null(int index);
  DbStatus bind_int64(int index, std::int64_t value);
  DbStatus bind_double(int index, double value);
  DbStatus bind_text(int index, std::string_view value);
  DbStatus bind_blob(int index, BlobView value);
  DbError error(const char* what, int code) const;

  sqlite3* db_ = nullptr;
  sqlite3_stmt* stmt_ = nullptr;
  std::string db_path_;
};

namespace detail {
template <class T>
struct IsOptional : std::false_type {};
template <class T>
struct IsOptional<std::optional<T>> : std::true_type {};
}  // namespace detail

template <class T>
DbStatus Statement::bind(int index, const T& value) {
  if constexpr (std::is_same_v<T, std::nullptr_t> || std::is_same_v<T, std::nullopt_t>) {
    return bind_null(index);
  } else if constexpr (detail::IsOptional<T>::value) {
    if (!value.has_value()) return bind_null(index);
    return bind(index, *value);
  } else if constexpr (std::is_same_v<T, bool>) {
    return bind_int64(index, value ? 1 : 0);
  } else if constexpr (std::is_integral_v<T>) {
    return bind_int64(index, static_cast<std::int64_t>(value));
  } else if constexpr (std::is_floating_point_v<T>) {
    return bind_double(index, static_cast<double>(value));
  } else if constexpr (std::is_same_v<T, BlobView>) {
    return bind_blob(index, value);
  } else if constexpr (std::is_convertible_v<const T&, std::string_view>) {
    return bind_text(index, std::string_view(value));
  } else {
    static_assert(sizeof(T) == 0, "Statement::bind: unsupported parameter type");
  }
}

template <class OnRow>
DbStatus Statement::for_each_row(OnRow on_row) {
  for (;;) {
    DbResult<bool> row = step();
    if (!row) return row.error();
    if (!row.value()) return {};
    if constexpr (std::is_same_v<std::invoke_result_t<OnRow>, DbStatus>) {
      if (DbStatus status = on_row(); !status) return status;
    } else {
      on_row();
    }
  }
}

template <class Items, class BindItem, class RowName>
DbStatus Statement::run_for_each(const Items& items, BindItem bind_item, RowName row_name) {
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (DbStatus b = bind_item(i, items[i]); !b) return b;
    if (DbStatus r = run(); !r) {
      return DbError{row_name(i) + ": " + r.error().message, r.error().sqlite_code};
    }
    if (DbStatus r = reset(); !r) return r;
  }
  return {};
}

}  // namespace acdr
