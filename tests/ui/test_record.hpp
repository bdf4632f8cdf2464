// A training record with a few real attempts for the dashboard tests, made by the attempt
// session (what `acdr run --headless` runs) on the test box without material (fast): trainee t-ann passes, fails (a rough scoop with
// overload warnings), then passes twice (mastered); t-ben passes once and fails once.
// Shared by the dashboard tests, never copied.
#pragma once

#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "app/attempt_session.hpp"
#include "tests/app/test_scenes.hpp"

namespace acdr::test {

/// Runs one replay attempt of the empty test box into `db`; returns false on failure.
inline bool add_replay_attempt(const std::string& db, const std::string& trainee,
                               const std::string& trajectory) {
  SessionOptions o;
  o.scenario = kSceneData + "empty_box.json";
  o.input = "replay:" + kSceneData + trajectory;
  o.trainee = trainee;
  o.db = db;
  std::ostringstream notes;
  const SessionResult result = run_attempt_session(o, nullptr, notes);
  EXPECT_EQ(result.end, SessionEnd::kCompleted) << result.error << notes.str();
  return result.end == SessionEnd::kCompleted;
}

/// The record described above, in `db`.
inline void make_test_record(const std::string& db) {
  for (const char* t : {"short_scoop.csv", "novice_scoop.csv", "short_scoop.csv",
                        "short_scoop.csv"})
    add_replay_attempt(db, "t-ann", t);
  add_replay_attempt(db, "t-ben", "short_scoop.csv");
  add_replay_attempt(db, "t-ben", "novice_scoop.csv");
}

}  // namespace acdr::test
