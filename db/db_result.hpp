// How the training-record store reports failure: a value or a DbError, never an exit().
// (C++20 has no std::expected; this is the small subset the store needs.)
#pragma once

#include <cassert>
#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace acdr {

/// A failed store operation. `message` names the database file, what was being done and what
/// SQLite said; `sqlite_code` is SQLite's extended result code (0 when the error is ours).
struct DbError {
  std::string message;
  int sqlite_code = 0;
};

/// Either a T or a DbError. Test with `ok()` or `if (result)`, then read `value()` or `error()`.
template <class T>
class [[nodiscard]] DbResult {
 public:
  DbResult(T value) : state_(std::in_place_index<0>, std::move(value)) {}
  DbResult(DbError error) : state_(std::in_place_index<1>, std::move(error)) {}

  bool ok() const { return state_.index() == 0; }
  explicit operator bool() const { return ok(); }

  T& value() & {
    assert(ok() && "DbResult::value() on an error");
    return std::get<0>(state_);
  }
  const T& value() const& {
    assert(ok() && "DbResult::value() on an error");
    return std::get<0>(state_);
  }
  /// On a temporary, moves the value out (returning a reference into a dying temporary would
  /// dangle in `for (auto& x : f().value())`).
  T value() && {
    assert(ok() && "DbResult::value() on an error");
    return std::get<0>(std::move(state_));
  }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

  const DbError& error() const {
    assert(!ok() && "DbResult::error() on a value");
    return std::get<1>(state_);
  }

 private:
  std::variant<T, DbError> state_;
};

/// Success, or a DbError.
template <>
class [[nodiscard]] DbResult<void> {
 public:
  DbResult() = default;
  DbResult(DbError error) : error_(std::move(error)) {}

  bool ok() const { return !error_.has_value(); }
  explicit operator bool() const { return ok(); }
  const DbError& error() const {
    assert(!ok() && "DbResult<void>::error() on success");
    return *error_;
  }

 private:
  std::optional<DbError> error_;
};

using DbStatus = DbResult<void>;

}  // namespace acdr
