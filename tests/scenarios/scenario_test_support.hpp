// Helpers shared by the scenario tests: reading the bundled files and finding where a piece of
// text sits, so expected line numbers are computed rather than hard-coded.
#pragma once

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "scenarios/scenario_error.hpp"

namespace acdr::test {

inline std::string source_path(const std::string& relative) {
  return std::string(ACDR_SOURCE_DIR) + "/" + relative;
}

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::string box_module_text() {
  return read_text(source_path("scenarios/modules/01_box_warmup.json"));
}

/// 1-based line of the first occurrence of `needle`; 0 when absent.
inline int line_of(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  if (at == std::string::npos) return 0;
  int line = 1;
  for (std::size_t i = 0; i < at; ++i) line += text[i] == '\n' ? 1 : 0;
  return line;
}

/// `text` with the first occurrence of `from` replaced by `to` (throws when absent, so a test
/// never silently mutates nothing).
inline std::string replace_once(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("not in text: " + from);
  text.replace(at, from.size(), to);
  return text;
}

}  // namespace acdr::test
