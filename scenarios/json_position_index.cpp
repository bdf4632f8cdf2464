// A single forward scan over JSON text with an explicit stack (no recursion, so nesting depth
// cannot overflow the call stack).
#include "scenarios/json_position_index.hpp"

#include <algorithm>
#include <map>

#include <nlohmann/json.hpp>

namespace acdr {

std::string escape_pointer_token(std::string_view token) {
  std::string out;
  out.reserve(token.size());
  for (char c : token) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

struct Frame {
  bool object = false;
  bool recorded = false;        ///< its children's pointers are recorded
  std::string pointer;          ///< empty when not recorded (and for the root)
  std::size_t next_index = 0;   ///< index of the next item (array element or member)
  std::map<std::string, TextPosition> keys;  ///< objects: keys seen so far (duplicates)
};

}  // namespace

JsonPositionIndex JsonPositionIndex::lines_only(std::string_view text) {
  JsonPositionIndex index;
  index.index_lines(text);
  return index;
}

void JsonPositionIndex::index_lines(std::string_view text) {
  line_starts_.assign(1, 0);
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '\n') line_starts_.push_back(i + 1);
  }
}

JsonPositionIndex::JsonPositionIndex(std::string_view text, std::vector<DuplicateKey>* duplicates) {
  index_lines(text);

  std::size_t pos = 0;
  const std::size_t n = text.size();
  if (n >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") pos = 3;  // UTF-8 byte-order mark
  auto skip_space = [&] {
    while (pos < n && is_space(text[pos])) ++pos;
  };
  // Moves past a string token starting at text[pos] == '"'; returns its raw text.
  auto skip_string = [&]() -> std::string_view {
    const std::size_t start = pos;
    ++pos;
    while (pos < n && text[pos] != '"') {
      pos += text[pos] == '\\' ? 2 : 1;
    }
    pos = std::min(pos + 1, n);
    return text.substr(start, pos - start);
  };
  auto skip_scalar = [&] {
    while (pos < n && !is_space(text[pos]) && text[pos] != ',' && text[pos] != ']' &&
           text[pos] != '}' && text[pos] != ':') {
      ++pos;
    }
  };

  std::vector<Frame> stack;
  // Reads the value starting at pos whose pointer is `pointer`, recorded at `where`.
  auto read_value = [&](std::string pointer, bool record, TextPosition where) {
    if (record) positions_.emplace(pointer, where);
    if (pos >= n) return;
    const char c = text[pos];
    if (c == '{' || c == '[') {
      Frame f;
      f.object = c == '{';
      f.recorded = record && static_cast<int>(stack.size()) < kMaxRecordedDepth;
      if (f.recorded) f.pointer = std::move(pointer);
      stack.push_back(std::move(f));
      ++pos;
    } else if (c == '"') {
      skip_string();
    } else {
      // Malformed input (a stray ':' or a closing bracket of the wrong kind) must still
      // consume a byte, or the scan would loop in place.
      const std::size_t before = pos;
      skip_scalar();
      if (pos == before) ++pos;
    }
  };

  skip_space();
  read_value(std::string(), true, position_of_offset(pos));
  while (!stack.empty()) {
    skip_space();
    if (pos >= n) break;
    Frame& top = stack.back();
    const char c = text[pos];
    if (c == (top.object ? '}' : ']')) {
      stack.pop_back();
      ++pos;
      continue;
    }
    if (c == ',') {
      ++pos;
      continue;
    }
    if (top.object) {
      if (c != '"') {  // malformed: skip one byte and carry on
        ++pos;
        continue;
      }
      const TextPosition key_pos = position_of_offset(pos);
      const std::string_view raw = skip_string();
      skip_space();
      if (pos < n && text[pos] == ':') ++pos;
      skip_space();
      if (!top.recorded || top.next_index++ >= kMaxRecordedItems) {
        read_value(std::string(), false, key_pos);
        continue;
      }
      // Decode escapes in the key exactly as the parser did.
      std::string key;
      nlohmann::json decoded = nlohmann::json::parse(raw, nullptr, false);
      if (decoded.is_string()) key = decoded.get<std::string>();
      else key = std::string(raw);
      std::string pointer = top.pointer + "/" + escape_pointer_token(key);
      auto [it, inserted] = top.keys.emplace(key, key_pos);
      if (!inserted && duplicates != nullptr) {
        duplicates->push_back({pointer, it->second, key_pos});
      }
      read_value(std::move(pointer), true, key_pos);
    } else {
      const TextPosition value_pos = position_of_offset(pos);
      const std::size_t index = top.next_index++;
      if (top.recorded && index < kMaxRecordedItems) {
        read_value(top.pointer + "/" + std::to_string(index), true, value_pos);
      } else {
        read_value(std::string(), false, value_pos);
      }
    }
  }
}

TextPosition JsonPositionIndex::find(const std::string& pointer) const {
  std::string p = pointer;
  while (true) {
    auto it = positions_.find(p);
    if (it != positions_.end()) return it->second;
    if (p.empty()) return {1, 1};
    const std::size_t slash = p.rfind('/');
    p.resize(slash == std::string::npos ? 0 : slash);
  }
}

TextPosition JsonPositionIndex::position_of_offset(std::size_t offset) const {
  if (line_starts_.empty()) return {1, 1};
  auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), offset);
  const std::size_t line = static_cast<std::size_t>(it - line_starts_.begin());  // >= 1
  return {static_cast<int>(line), static_cast<int>(offset - line_starts_[line - 1] + 1)};
}

}  // namespace acdr
