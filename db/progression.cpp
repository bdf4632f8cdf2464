// Progression queries: see progression.hpp for the rule.
#include "db/progression.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "db/catalog.hpp"

namespace acdr {

namespace {

struct ModuleHistory {
  std::vector<CountedOutcome> outcomes;
  std::optional<double> best_score;
  std::optional<double> last_score;
};

DbResult<ModuleHistory> read_history(Database& db, const std::string& trainee_id,
                                     const std::string& module_id) {
  DbResult<Statement> s = db.prepare(
      "SELECT status, passed, score FROM attempts "
      "WHERE trainee_id = ? AND module_id = ? AND status IN ('completed', 'aborted') "
      "ORDER BY started_utc, id");
  if (!s) return s.error();
  if (DbStatus b = s->bind_all(trainee_id, module_id); !b) return b.error();
  ModuleHistory h;
  for (;;) {
    DbResult<bool> row = s->step();
    if (!row) return row.error();
    if (!row.value()) break;
    if (s->column_text(0) == "aborted") {
      h.outcomes.push_back(CountedOutcome::kAborted);
      continue;
    }
    h.outcomes.push_back(s->column_int64(1) != 0 ? CountedOutcome::kPassed
                                                 : CountedOutcome::kFailed);
    if (std::optional<double> score = s->column_optional_double(2);
        score && std::isfinite(*score)) {
      h.last_score = score;
      h.best_score = h.best_score ? std::max(*h.best_score, *score) : *score;
    }
  }
  return h;
}

ModuleProgress progress_of(const ModuleRecord& module, const ModuleHistory& history,
                           const ProgressionOptions& options) {
  ModuleProgress p;
  p.module_id = module.id;
  p.title = module.title;
  p.curriculum_id = module.curriculum_id;
  p.position = module.position;
  p.required_consecutive = module.consecutive_passes_required;
  p.pass_score = module.pass_score;
  p.run = summarize_run(history.outcomes, module.consecutive_passes_required, options);
  p.passed = p.run.passes > 0;
  p.mastered = p.run.mastered;
  p.best_score = history.best_score;
  p.last_score = history.last_score;
  return p;
}

// Fills prerequisites, missing_prerequisites and unlocked, given who has mastered what.
DbStatus resolve_unlock(Database& db, const ModuleRecord& module,
                        const std::map<std::string, bool>& mastered_by_id, ModuleProgress& p) {
  DbResult<std::vector<std::string>> prereqs = effective_prerequisites(db, module);
  if (!prereqs) return prereqs.error();
  p.prerequisites = std::move(prereqs.value());
  p.missing_prerequisites.clear();
  for (const std::string& id : p.prerequisites) {
    auto it = mastered_by_id.find(id);
    if (it == mastered_by_id.end() || !it->second) p.missing_prerequisites.push_back(id);
  }
  p.unlocked = p.missing_prerequisites.empty();
  return {};
}

// Mastery of the given module ids for one trainee (unregistered ids are left out).
DbResult<std::map<std::string, bool>> mastery_of(Database& db, const std::string& trainee_id,
                                                 const std::vector<std::string>& module_ids,
                                                 const ProgressionOptions& options) {
  std::map<std::string, bool> out;
  for (const std::string& id : module_ids) {
    DbResult<std::optional<ModuleRecord>> m = find_module(db, id);
    if (!m) return m.error();
    if (!m.value()) continue;
    DbResult<ModuleHistory> h = read_history(db, trainee_id, id);
    if (!h) return h.error();
    out[id] = summarize_run(h->outcomes, m.value()->consecutive_passes_required, options).mastered;
  }
  return out;
}

}  // namespace

RunSummary summarize_run(std::span<const CountedOutcome> outcomes, int required_consecutive,
                         const ProgressionOptions& options) {
  RunSummary r;
  const int required = std::max(1, required_consecutive);
  int run = 0;
  for (CountedOutcome outcome : outcomes) {
    if (outcome == CountedOutcome::kAborted && !options.aborted_attempts_break_run) continue;
    ++r.attempts;
    if (outcome == CountedOutcome::kPassed) {
      ++r.passes;
      ++run;
    } else {
      run = 0;
    }
    r.longest_run = std::max(r.longest_run, run);
    if (!r.mastered && run >= required) {
      r.mastered = true;
      r.mastered_at = r.attempts;
    }
  }
  r.consecutive_at_end = run;
  return r;
}

const char* ModuleProgress::state_name() const {
  if (mastered) return "mastered";
  if (!unlocked) return "locked";
  if (run.attempts == 0) return "not started";
  return "in progress";
}

DbResult<ModuleProgress> module_progress(Database& db, const std::string& trainee_id,
                                         const std::string& module_id,
                                         const ProgressionOptions& options) {
  DbResult<Transaction> tx = Transaction::begin(db, Transaction::Mode::kDeferred);
  if (!tx) return tx.error();
  DbResult<std::optional<ModuleRecord>> module = find_module(db, module_id);
  if (!module) return module.error();
  if (!module.value()) {
    return DbError{db.path() + ": module '" + module_id + "' is not registered", 0};
  }
  DbResult<ModuleHistory> history = read_history(db, trainee_id, module_id);
  if (!history) return history.error();
  ModuleProgress p = progress_of(*module.value(), history.value(), options);

  DbResult<std::vector<std::string>> prereqs = effective_prerequisites(db, *module.value());
  if (!prereqs) return prereqs.error();
  DbResult<std::map<std::string, bool>> mastered =
      mastery_of(db, trainee_id, prereqs.value(), options);
  if (!mastered) return mastered.error();
  if (DbStatus u = resolve_unlock(db, *module.value(), mastered.value(), p); !u) return u.error();
  if (DbStatus c = tx->commit(); !c) return c.error();
  return p;
}

DbResult<std::vector<ModuleProgress>> trainee_progress(
    Database& db, const std::string& trainee_id, const std::optional<std::string>& curriculum_id,
    const ProgressionOptions& options) {
  DbResult<Transaction> tx = Transaction::begin(db, Transaction::Mode::kDeferred);
  if (!tx) return tx.error();
  // Mastery of every module first (prerequisites may lie outside the listed curriculum).
  DbResult<std::vector<ModuleRecord>> all = list_modules(db);
  if (!all) return all.error();
  std::map<std::string, bool> mastered;
  std::vector<ModuleProgress> out;
  std::vector<const ModuleRecord*> listed;
  for (const ModuleRecord& m : all.value()) {
    DbResult<ModuleHistory> h = read_history(db, trainee_id, m.id);
    if (!h) return h.error();
    ModuleProgress p = progress_of(m, h.value(), options);
    mastered[m.id] = p.mastered;
    if (!curriculum_id || m.curriculum_id == curriculum_id) {
      out.push_back(std::move(p));
      listed.push_back(&m);
    }
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (DbStatus u = resolve_unlock(db, *listed[i], mastered, out[i]); !u) return u.error();
  }
  if (DbStatus c = tx->commit(); !c) return c.error();
  return out;
}

DbResult<UnlockDecision> check_unlocked(Database& db, const std::string& trainee_id,
                                        const std::string& module_id,
                                        const ProgressionOptions& options) {
  DbResult<ModuleProgress> p = module_progress(db, trainee_id, module_id, options);
  if (!p) return p.error();
  UnlockDecision d;
  d.unlocked = p->unlocked;
  d.missing_prerequisites = p->missing_prerequisites;
  if (!d.unlocked) {
    // Say what each missing module needs, so the trainee knows what to do next.
    d.reason = "module '" + module_id + "' is locked for trainee '" + trainee_id + "': ";
    for (std::size_t i = 0; i < d.missing_prerequisites.size(); ++i) {
      const std::string& id = d.missing_prerequisites[i];
      if (i > 0) d.reason += "; ";
      DbResult<std::optional<ModuleRecord>> m = find_module(db, id);
      if (!m) return m.error();
      if (!m.value()) {
        d.reason += "prerequisite '" + id + "' is not registered";
      } else {
        d.reason += "pass '" + id + "' on " +
                    std::to_string(m.value()->consecutive_passes_required) +
                    " attempts in a row first";
      }
    }
    d.reason += " (or an instructor may override)";
  }
  return d;
}

}  // namespace acdr
