// Typed, located reads of one JSON object of a scenario file. Each read checks presence, type,
// unit spelling and range, reports any problem with the key's line and JSON path, and converts
// to SI once. `finish()` then reports every key that was not asked for as unknown, with the
// nearest known key as a suggestion. The loader is written as a sequence of these reads.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/core/types.hpp"
#include "scenarios/json_position_index.hpp"
#include "scenarios/key_registry.hpp"
#include "scenarios/scenario_error.hpp"

namespace acdr {

/// Whether a key must be present. kRequiredHere: required in this file because of another
/// key (e.g. a removal region because a nucleus is declared); the format lists it as optional.
enum class Need { kOptional, kRequired, kRequiredHere };

/// An allowed interval, in SI units. Unset bounds are open.
struct Range {
  std::optional<double> min, max;
  bool min_exclusive = false;
  bool max_exclusive = false;

  static Range any() { return {}; }
  /// min < x <= max
  static Range positive(double max) { return {0.0, max, true, false}; }
  /// min <= x <= max
  static Range closed(double min, double max) { return {min, max, false, false}; }
};

/// One spelling of a quantity's key: the key and the factor to SI ("spacing_mm", 1e-3, "mm").
struct UnitKey {
  std::string key;
  double to_si;
  const char* symbol;  ///< unit as written in messages ("" for dimensionless)
};

/// State shared by all readers of one file: where errors go and where positions come from.
class LoadContext {
 public:
  /// After this many errors the rest are dropped with one closing note (a garbage file must not
  /// print a million lines).
  static constexpr std::size_t kMaxErrors = 200;

  LoadContext(std::string file, const JsonPositionIndex& index, KeyRegistry* registry)
      : file_(std::move(file)), index_(index), registry_(registry) {}

  /// Records an error at `pointer` (its line found through the index).
  void error(const std::string& pointer, std::string message);
  /// Records an error at `pointer` but located at the line of `located_at`.
  void error_located(const std::string& pointer, const std::string& located_at, std::string message);
  void record(const KeyInfo& info) {
    if (registry_ != nullptr) registry_->record(info);
  }
  std::size_t error_count() const { return errors_.size(); }
  std::vector<ScenarioError>& errors() { return errors_; }

 private:
  std::string file_;
  const JsonPositionIndex& index_;
  KeyRegistry* registry_;
  std::vector<ScenarioError> errors_;
  bool truncated_ = false;
};

/// A short description of a value for "got X" (containers by kind and size, never dumped whole).
std::string describe_value(const nlohmann::json& value);
/// A number for messages: up to 9 significant digits.
std::string format_number(double x);

class ObjectReader {
 public:
  /// `value` must outlive the reader. When it is not an object, one type error is reported and
  /// every read returns nothing.
  ObjectReader(LoadContext& ctx, const nlohmann::json& value, std::string pointer,
               std::string pattern);

  bool valid() const { return object_ != nullptr; }
  const std::string& pointer() const { return pointer_; }
  LoadContext& context() const { return *ctx_; }
  /// Pointer of a key of this object.
  std::string child(const std::string& key) const;
  bool has(const std::string& key) const;

  /// A dimensionless number (unit symbol only for messages, e.g. "Pa·s" is in the key name).
  std::optional<double> number(const std::string& key, Need need, const Range& range,
                               const char* unit_symbol = "");
  /// An integer (1 and 1.0 both accepted, as JSON Schema does). `hint` completes the
  /// "expected" text of a missing-key error ("the format version, 1").
  std::optional<int> integer(const std::string& key, Need need, const Range& range,
                             const std::string& hint = "");
  /// A quantity in one of several unit spellings (not two at once), converted to SI; the range
  /// is in SI.
  std::optional<double> quantity(const std::vector<UnitKey>& spellings, Need need,
                                 const Range& si_range);
  /// A 3-vector [x, y, z] in one of several unit spellings, converted to SI; each component
  /// must be finite and inside `si_range`.
  std::optional<Vec3> vector3(const std::vector<UnitKey>& spellings, Need need,
                              const Range& si_range);
  /// An array of exactly `count` numbers.
  std::optional<std::vector<double>> numbers(const std::string& key, Need need, std::size_t count);
  /// A string; `nonempty` rejects ""; `allowed` (when not empty) limits its values, to which
  /// `value_pattern` (an anchored ECMAScript regex, when not empty) adds every matching text.
  std::optional<std::string> string(const std::string& key, Need need, bool nonempty = true,
                                    const std::vector<std::string>& allowed = {},
                                    const std::string& hint = "",
                                    const std::string& value_pattern = "");
  std::optional<bool> boolean(const std::string& key, Need need);
  /// A nested object.
  std::optional<ObjectReader> object(const std::string& key, Need need);
  /// An array of objects with at least `min_items` items; one reader per item that is an object.
  std::vector<ObjectReader> objects(const std::string& key, Need need, std::size_t min_items);
  /// Any value, for keys read by hand; `type` is its JSON Schema type for the registry.
  const nlohmann::json* raw(const std::string& key, Need need, const std::string& type,
                            const std::string& expected);

  /// Reports every key present but never asked for. Call once, after all reads.
  void finish();

 private:
  bool pick_spelling(const std::vector<UnitKey>& spellings, Need need, const char* json_type,
                     int items, const Range& si_range, const std::string& expected,
                     const UnitKey** chosen, const nlohmann::json** value);
  const nlohmann::json* lookup(const std::string& key, Need need, const std::string& expected);
  void remember(const std::string& key);
  std::string child_pattern(const std::string& key) const;
  bool check_range(const std::string& key, double value_in_si, double shown_value, const Range& si_range,
                   double to_si, const char* symbol);

  LoadContext* ctx_;
  const nlohmann::json* object_ = nullptr;
  std::string pointer_;
  std::string pattern_;
  std::vector<std::string> asked_;           ///< every key this object may hold
  std::vector<std::vector<std::string>> groups_;  ///< alternative spellings, for suggestions
};

}  // namespace acdr
