// Where each JSON value sits in the text. nlohmann's DOM keeps no source positions, so the
// loader scans the (already parsed, hence well-formed) text once and maps every JSON pointer
// to the line and column of its key (object members) or of the value (array items and root).
// It also finds duplicate keys, which the DOM would silently collapse to the last one.
#pragma once

#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace acdr {

/// 1-based line and byte column; {0, 0} means unknown.
struct TextPosition {
  int line = 0;
  int column = 0;
};

/// A key that appears twice in one object.
struct DuplicateKey {
  std::string json_path;  ///< pointer of the key (as the later occurrence)
  TextPosition first;
  TextPosition second;
};

class JsonPositionIndex {
 public:
  /// Pointers deeper than this are not recorded: the scenario format is shallower, and bounding
  /// it keeps a pathological file (e.g. a million nested arrays) linear in time and memory.
  static constexpr int kMaxRecordedDepth = 32;
  /// Items (array elements or object members) recorded per container, for the same reason.
  static constexpr std::size_t kMaxRecordedItems = 10000;

  JsonPositionIndex() = default;
  /// Scans `text`, which should be valid JSON (malformed parts are skipped, never read past the
  /// end). Duplicate keys are appended to `duplicates` when it is given.
  explicit JsonPositionIndex(std::string_view text, std::vector<DuplicateKey>* duplicates = nullptr);

  /// Only line starts, for positions of byte offsets (e.g. of a parse error).
  static JsonPositionIndex lines_only(std::string_view text);

  /// Position of `pointer`; when it is not recorded (a missing key, or too deep), the position
  /// of its nearest recorded ancestor; {1, 1} for an empty text.
  TextPosition find(const std::string& pointer) const;

  /// Line and column of a byte offset into the indexed text (clamped to its end).
  TextPosition position_of_offset(std::size_t offset) const;

 private:
  void index_lines(std::string_view text);

  std::vector<std::size_t> line_starts_;  ///< byte offset of each line's first byte
  std::unordered_map<std::string, TextPosition> positions_;
};

/// RFC 6901 escaping of one reference token: "~" -> "~0", "/" -> "~1".
std::string escape_pointer_token(std::string_view token);

}  // namespace acdr
