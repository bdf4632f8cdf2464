// Names of attempt states as stored in the attempts.status column: see records.hpp.
#include "db/records.hpp"

namespace acdr {

const char* attempt_status_name(AttemptStatus status) {
  switch (status) {
    case AttemptStatus::kRunning: return "running";
    case AttemptStatus::kCompleted: return "completed";
    case AttemptStatus::kAborted: return "aborted";
  }
  return "running";
}

std::optional<AttemptStatus> parse_attempt_status(std::string_view text) {
  if (text == "running") return AttemptStatus::kRunning;
  if (text == "completed") return AttemptStatus::kCompleted;
  if (text == "aborted") return AttemptStatus::kAborted;
  return std::nullopt;
}

}  // namespace acdr
