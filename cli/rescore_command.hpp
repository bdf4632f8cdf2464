// `acdr rescore`: re-scores stored attempts from their recordings with the current rubric of
// their module's scenario file, and stores the new metrics and score. Aborted attempts get their
// metrics re-computed from what was checkpointed, and stay aborted, unscored and not passed.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace acdr {

struct RescoreOptions {
  std::string db;                        ///< empty: default_database_path()
  std::optional<std::string> trainee;    ///< only this trainee's attempts
  std::optional<std::string> module;     ///< only attempts at this module
  std::optional<long long> attempt;      ///< only this attempt
  bool dry_run = false;                  ///< compute and print, store nothing
};

/// Exit codes: 0 done, 2 bad input (database, scenario file, damaged recording).
int run_rescore(const RescoreOptions& options, std::ostream& out, std::ostream& err);

}  // namespace acdr
