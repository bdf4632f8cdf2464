// Curriculum progression from the record: per trainee and module, how many attempts, the
// passing run at the end, whether the module is mastered, and whether it is unlocked.
//
// The rule (proficiency-based, as FLS and the da Vinci MScore curricula use, docs/references.md
// "Assessment anchors"): a module is mastered once the trainee has passed it on
// `consecutive_passes_required` attempts in a row (default 2, stored with the module). Mastery
// is kept once reached: a later failed attempt does not re-lock what the trainee has shown. A
// module is unlocked when every prerequisite (catalog.hpp: effective_prerequisites) is
// mastered. Only completed and aborted attempts of that trainee count, in start order; an
// aborted attempt is not a pass and by default breaks the run (mastery must be shown in
// attempts taken to the end). Practice attempts (no trainee) never count, and running attempts
// are not yet an outcome.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "db/database.hpp"
#include "db/records.hpp"

namespace acdr {

/// How one counted attempt ended.
enum class CountedOutcome { kPassed, kFailed, kAborted };

struct ProgressionOptions {
  /// true: an aborted attempt resets the passing run (default); false: it is skipped.
  bool aborted_attempts_break_run = true;
};

/// The run statistics of one trainee on one module.
struct RunSummary {
  int attempts = 0;            ///< counted attempts (completed + aborted)
  int passes = 0;              ///< passing attempts
  int consecutive_at_end = 0;  ///< passing attempts in a row at the end of the sequence
  int longest_run = 0;         ///< longest run of passing attempts in a row
  bool mastered = false;       ///< longest_run >= required
  int mastered_at = 0;         ///< 1-based attempt that completed mastery; 0 = not mastered
};

/// The rule as a pure function over outcomes in start order.
RunSummary summarize_run(std::span<const CountedOutcome> outcomes, int required_consecutive,
                         const ProgressionOptions& options = {});

struct ModuleProgress {
  std::string module_id;
  std::string title;
  std::optional<std::string> curriculum_id;
  int position = 0;
  int required_consecutive = 2;
  double pass_score = 50.0;
  RunSummary run;
  bool passed = false;    ///< at least one passing attempt
  bool mastered = false;  ///< run.mastered
  bool unlocked = false;  ///< every prerequisite mastered (true when there are none)
  std::vector<std::string> prerequisites;          ///< effective prerequisites
  std::vector<std::string> missing_prerequisites;  ///< not mastered, or not registered
  std::optional<double> best_score;
  std::optional<double> last_score;

  /// "mastered", "locked", "not started" or "in progress".
  const char* state_name() const;
};

/// Progress of `trainee_id` on one module. Error if the module is not registered.
DbResult<ModuleProgress> module_progress(Database& db, const std::string& trainee_id,
                                         const std::string& module_id,
                                         const ProgressionOptions& options = {});

/// Progress of `trainee_id` on every module (of one curriculum when given), in curriculum
/// order.
DbResult<std::vector<ModuleProgress>> trainee_progress(
    Database& db, const std::string& trainee_id,
    const std::optional<std::string>& curriculum_id = std::nullopt,
    const ProgressionOptions& options = {});

/// Whether a trainee may take a module, and if not, why in words (for `acdr run`, which
/// refuses a locked module unless an instructor overrides). Practice attempts are never
/// locked: do not ask.
struct UnlockDecision {
  bool unlocked = false;
  std::vector<std::string> missing_prerequisites;
  std::string reason;  ///< empty when unlocked
};
DbResult<UnlockDecision> check_unlocked(Database& db, const std::string& trainee_id,
                                        const std::string& module_id,
                                        const ProgressionOptions& options = {});

}  // namespace acdr
