// Formatting of scenario errors in the compiler-like form editors can jump to.
#include "scenarios/scenario_error.hpp"

namespace acdr {

std::string ScenarioError::to_string() const {
  std::string out = file;
  out += ':';
  out += std::to_string(line);
  out += ": ";
  if (!json_path.empty()) {
    out += json_path;
    out += ": ";
  }
  out += message;
  return out;
}

std::string to_string(const std::vector<ScenarioError>& errors) {
  std::string out;
  for (const ScenarioError& e : errors) {
    out += e.to_string();
    out += '\n';
  }
  return out;
}

}  // namespace acdr
