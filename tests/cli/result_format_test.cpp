// Tests of cli/result_format: the summary and the JSON of a session's result — the score table
// as the terminal prints it, and the live parts (haptics, checkpoints) only when there were.
#include "cli/result_format.hpp"

#include <gtest/gtest.h>

#include "scenarios/scenario_loader.hpp"
#include "tests/app/test_scenes.hpp"

namespace acdr {
namespace {

SessionResult stored_result() {
  SessionResult r;
  LoadResult loaded = load_scenario_file(test::kSceneData + "empty_box.json");
  EXPECT_TRUE(loaded.ok()) << to_string(loaded.errors);
  r.scenario = loaded.model;
  r.world = std::make_unique<World>(r.scenario->world);
  r.end = SessionEnd::kCompleted;
  r.run.end = AttemptEnd::kTimeLimit;
  r.run.metrics.set("nucleus_removed_fraction", 0.05);
  r.run.metrics.set("overload_events", 2.0);
  r.run.score.score = 31.0;
  r.run.score.terms = {{"nucleus_removed_fraction", 0.05, 30.0}};
  r.run.score.gates = {{"overload_events", 2.0, 0.0, false}};
  r.attempt_id = 7;
  r.db_path = "record.sqlite";
  r.stored_as = "completed";
  return r;
}

TEST(ResultFormat, TheSummaryListsTheScoredMetricsThenTheGates) {
  const SessionResult r = stored_result();
  const std::string s = result_summary(r, "");
  // A term: a column for the safety mark (blank here), the metric, value, score, benchmark.
  const std::string term = "      nucleus_removed_fraction         0.05  ->  30.0 / 100  (benchmark unknown)\n";
  const std::string gate = "    gate overload_events                  2  (max 0) FAILED\n";
  ASSERT_NE(s.find(term), std::string::npos) << s;
  ASSERT_NE(s.find(gate), std::string::npos) << s;
  EXPECT_LT(s.find(term), s.find(gate));
  EXPECT_NE(s.find("  stored as attempt 7 (completed) in record.sqlite\n"), std::string::npos);
  EXPECT_NE(s.find("  how to read it:\n    50 = the experts' mean"), std::string::npos) << s;
  EXPECT_EQ(s.find("haptic loop"), std::string::npos);  // not a live attempt
  EXPECT_EQ(s.find("checkpoints"), std::string::npos);
  EXPECT_EQ(s.find("picture"), std::string::npos);
}

TEST(ResultFormat, LivePartsAppearOnlyForALiveAttempt) {
  SessionResult r = stored_result();
  nlohmann::json j = result_json(r, "");
  EXPECT_FALSE(j.contains("haptics"));
  EXPECT_FALSE(j.contains("checkpoints"));
  EXPECT_FALSE(j.contains("png"));
  EXPECT_EQ(j["gates"][0]["metric"], "overload_events");
  EXPECT_EQ(j["terms"][0]["score"], 30.0);
  EXPECT_EQ(j["end"], "time limit");

  r.haptics.emplace().loop.rate_hz = 998.0;
  r.checkpoints = CheckpointReport{0.5, {}};
  r.checkpoints->stats.saved = 3;
  j = result_json(r, "final.png");
  EXPECT_EQ(j["haptics"]["rate_hz"], 998.0);
  EXPECT_EQ(j["checkpoints"]["every_s"], 0.5);
  EXPECT_EQ(j["checkpoints"]["saved"], 3);
  EXPECT_EQ(j["png"], "final.png");
  const std::string s = result_summary(r, "final.png");
  EXPECT_NE(s.find("  haptic loop               998.0 Hz"), std::string::npos) << s;
  EXPECT_NE(s.find("  picture of the final frame: final.png\n"), std::string::npos);
  EXPECT_NE(s.find("  checkpoints            3 saved every 0.5 s"), std::string::npos) << s;
}

TEST(ResultFormat, AnAttemptWithATraySaysWhichInstrumentWasInHandWhen) {
  SessionResult r = stored_result();
  // Without a tray: no line, no field.
  EXPECT_EQ(result_summary(r, "").find("instruments"), std::string::npos);
  EXPECT_FALSE(result_json(r, "").contains("instruments"));
  auto scenario = std::make_shared<ScenarioModel>(*r.scenario);
  InstrumentConfig rongeur, cup;
  rongeur.name = "pituitary rongeur";
  cup.name = "cup curette";
  scenario->world.instruments = {rongeur, cup};
  r.scenario = scenario;
  r.run.record.events.push_back(Event{71.29, EventKind::kInstrumentExchange, 1.0, "cup curette"});
  const std::string s = result_summary(r, "");
  EXPECT_NE(s.find("  instruments            pituitary rongeur from 0.00 s, cup curette from 71.29 s\n"),
            std::string::npos)
      << s;
  const nlohmann::json j = result_json(r, "");
  ASSERT_EQ(j["instruments"].size(), 2u);
  EXPECT_EQ(j["instruments"][0]["name"], "pituitary rongeur");
  EXPECT_EQ(j["instruments"][1]["from_s"], 71.29);
  EXPECT_EQ(j["instruments"][1]["name"], "cup curette");
}

}  // namespace
}  // namespace acdr
