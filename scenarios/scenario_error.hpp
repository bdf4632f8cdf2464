// One problem found in a scenario file, located by file, line and JSON path, so an author can
// go straight to it. The loader collects all of them rather than stopping at the first.
#pragma once

#include <string>
#include <vector>

namespace acdr {

struct ScenarioError {
  std::string file;       ///< the path given to the loader (as the user typed it)
  int line = 0;           ///< 1-based line of the offending key or value; 0 when unknown
  int column = 0;         ///< 1-based byte column; 0 when unknown
  std::string json_path;  ///< JSON pointer (RFC 6901) of the key, "" for the whole document
  std::string message;    ///< what is wrong, with "(got X, expected Y)" where that applies

  /// `file:line: /json/path: message` (the path is left out when it is empty).
  std::string to_string() const;
};

/// All errors, one per line, in the order found.
std::string to_string(const std::vector<ScenarioError>& errors);

}  // namespace acdr
