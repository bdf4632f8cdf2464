// Re-scoring: metrics come from the recording alone (assessment never reads engine internals),
// so a stored attempt can be judged again under a newer rubric. An aborted attempt's metrics
// are re-computed from its checkpointed recording; it is never scored.
#include "cli/rescore_command.hpp"

#include <cstdio>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "app/bone_metrics_replay.hpp"
#include "assessment/metrics.hpp"
#include "assessment/recording.hpp"
#include "assessment/scoring.hpp"
#include "db/attempt_store.hpp"
#include "db/catalog.hpp"
#include "scenarios/scenario_loader.hpp"

namespace acdr {

int run_rescore(const RescoreOptions& options, std::ostream& out, std::ostream& err) {
  const std::string db_path = options.db.empty() ? default_database_path() : options.db;
  OpenOptions open;
  open.create = false;
  std::vector<std::string> notes;  // results of earlier attempts stored from side files
  auto db = open_store(db_path, open, &notes);
  for (const std::string& line : notes) err << "note: " << line << "\n";
  if (!db) {
    err << db.error().message << "\n";
    return 2;
  }
  AttemptFilter filter;
  filter.trainee_id = options.trainee;
  filter.module_id = options.module;
  auto attempts = list_attempts(db.value(), filter, {});
  if (!attempts) {
    err << attempts.error().message << "\n";
    return 1;  // an accepted record that could not be read
  }

  std::map<std::string, std::shared_ptr<const ScenarioModel>> scenarios;  // by module id
  BoneMetricsReplay bone;  // the bone models of the last module, built once
  int rescored = 0, changed = 0;
  for (const AttemptRecord& row : attempts.value()) {
    if (options.attempt && row.id != *options.attempt) continue;
    // A running attempt is still being written. An aborted one is re-computed from what was
    // checkpointed, but stays aborted, unscored and not passed (it never counts toward
    // progression); one aborted before its first checkpoint has nothing to re-compute.
    if (row.status == AttemptStatus::kRunning) continue;
    const bool aborted = row.status == AttemptStatus::kAborted;

    // The module's scenario file gives the current rubric (an aborted attempt needs none).
    auto& scenario = scenarios[row.module_id];
    if (!scenario && !aborted) {
      auto module = find_module(db.value(), row.module_id);
      if (!module || !module.value()) {
        err << db_path << ": attempt " << row.id << ": module '" << row.module_id
            << "' is not registered\n";
        return 2;
      }
      const LoadResult loaded = load_scenario_file(module.value()->scenario_path);
      if (!loaded.ok()) {
        err << to_string(loaded.errors);
        return 2;
      }
      scenario = loaded.model;
    }

    auto full = load_attempt(db.value(), row.id, {true, false, true});
    if (!full) {
      err << full.error().message << "\n";
      return 2;
    }
    if (aborted && full.value() && !full.value()->recording) {
      char line[200];
      std::snprintf(line, sizeof line,
                    "attempt %lld (%s): aborted before its first checkpoint, nothing to "
                    "re-score\n",
                    static_cast<long long>(row.id), row.module_id.c_str());
      out << line;
      continue;
    }
    if (!full.value() || !full.value()->recording) {
      err << db_path << ": attempt " << row.id << " has no recording to re-score from\n";
      return 2;
    }
    const RecordingData& data = *full.value()->recording;
    if (!is_known_recording_format(data.format)) {
      err << db_path << ": attempt " << row.id << ": recording format '" << data.format
          << "' (expected " << kRecordingFormat << " or " << kRecordingFormatV1 << ")\n";
      return 2;
    }
    std::string error;
    const auto recording = decode_recording(data.bytes, &error);
    if (!recording) {
      err << db_path << ": attempt " << row.id << ": " << error << "\n";
      return 2;
    }
    Metrics metrics = compute_metrics(*recording);
    // The bone's stresses, solved again from the recorded loads (not for an aborted attempt,
    // whose checkpoints do not carry them).
    if (!aborted && !bone.add_metrics(*scenario, *recording, metrics, &error)) {
      err << db_path << ": attempt " << row.id << ": bone model: " << error << "\n";
      return 2;
    }
    const bool metrics_same = metrics.values == full.value()->metrics.values;
    char line[200];
    if (aborted) {
      std::snprintf(line, sizeof line,
                    "attempt %lld (%s): aborted, not scored (%zu checkpointed frames)%s\n",
                    static_cast<long long>(row.id), row.module_id.c_str(),
                    recording->frames.size(),
                    metrics_same ? ", metrics identical" : ", metrics changed");
      out << line;
      ++rescored;
      if (!metrics_same) ++changed;
      if (!options.dry_run && !metrics_same) {
        if (auto stored = update_aborted_metrics(db.value(), row.id, metrics); !stored) {
          err << stored.error().message << "\n";
          return 2;
        }
      }
      continue;
    }
    const ScoreResult score = score_attempt(metrics, scenario->rubric);
    const double old_score = row.score.value_or(0.0);
    std::snprintf(line, sizeof line, "attempt %lld (%s): score %.2f -> %.2f%s%s\n",
                  static_cast<long long>(row.id), row.module_id.c_str(), old_score, score.score,
                  score.passed ? " passed" : " not passed",
                  metrics_same ? ", metrics identical" : ", metrics changed");
    out << line;
    ++rescored;
    if (!metrics_same || score.score != old_score) ++changed;
    if (!options.dry_run) {
      if (auto stored = update_attempt_assessment(db.value(), row.id, metrics, score); !stored) {
        err << stored.error().message << "\n";
        return 2;
      }
    }
  }
  out << rescored << " attempt(s) re-scored, " << changed << " changed"
      << (options.dry_run ? " (dry run: nothing stored)" : "") << "\n";
  return 0;
}

}  // namespace acdr
