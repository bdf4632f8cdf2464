// The scenario format's key set as the loader actually reads it. Every typed read of the
// loader records what it asked for (path pattern, JSON type, bounds, allowed values), so a test
// can compare the loader with scenario.schema.json and neither can drift from the other.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace acdr {

/// One key of the format. Bounds are in the unit of the key's own spelling (e.g. mm for
/// "spacing_mm"), as the schema states them.
struct KeyInfo {
  std::string pattern;   ///< JSON pointer with "*" for array items, e.g. "/rubric/terms/*/metric"
  std::string type;      ///< JSON Schema type: number, integer, string, boolean, object, array;
                         ///< "integer|string" where either is accepted
  bool required = false; ///< required on its own (alternative spellings: see `alternatives`)
  bool group_required = false;  ///< one of this key and its alternatives is required
  std::optional<double> minimum, maximum, exclusive_minimum, exclusive_maximum;
  std::optional<std::size_t> min_items, max_items;  ///< arrays
  std::vector<std::string> enum_values;             ///< strings limited to these
  std::string value_pattern;  ///< ... or matching this regex (schema: anyOf enum / pattern)
  std::vector<std::string> alternatives;            ///< other unit spellings, not both at once
};

class KeyRegistry {
 public:
  /// Records `info` (a key read twice keeps its first record).
  void record(const KeyInfo& info) { keys_.emplace(info.pattern, info); }
  const std::map<std::string, KeyInfo>& keys() const { return keys_; }

 private:
  std::map<std::string, KeyInfo> keys_;
};

}  // namespace acdr
