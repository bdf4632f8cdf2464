// Tests of db/xapi.cpp: every statement has the fields an LRS and the issue require, and the
// cmi5 rules hold (one `passed` per registration, scaled score against masteryScore).
#include "db/xapi.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <cmath>
#include <fstream>
#include <limits>
#include <regex>
#include <set>
#include <sstream>

#include "db/report.hpp"
#include "db/uuid.hpp"
#include "tests/db/db_test_support.hpp"
#include "tests/support/test_lrs_process.hpp"

namespace acdr {
namespace {

using test::add_attempt;
using test::minute;

class XapiTest : public ::testing::Test {
 protected:
  void SetUp() override {
    db_ = test::open_or_fail(dir_.file("record.sqlite"));
    test::register_curriculum(db_, 2);
  }
  nlohmann::json statements(std::optional<std::string> trainee = std::nullopt) {
    ReportRequest r;
    r.format = ReportFormat::kXapi;
    r.trainee_id = std::move(trainee);
    std::ostringstream out;
    DbStatus s = write_report(db_, r, out);
    EXPECT_TRUE(s.ok()) << s.error().message;
    return nlohmann::json::parse(out.str());
  }
  static std::string verb_of(const nlohmann::json& st) {
    const std::string id = st["verb"]["id"];
    return id.substr(id.rfind('/') + 1);
  }

  test::TempDir dir_;
  Database db_;
};

TEST_F(XapiTest, EveryStatementHasTheRequiredFields) {
  add_attempt(db_, "t1", "m1", 82.5, true, minute(0));
  add_attempt(db_, "t1", "m1", 31.0, false, minute(1));
  const nlohmann::json all = statements();
  ASSERT_TRUE(all.is_array());
  ASSERT_EQ(all.size(), 4u);  // scored+passed, scored+failed
  const std::regex duration(R"(^PT(\d+(\.\d+)?S)$)");
  const std::set<std::string> adl_verbs = {"http://adlnet.gov/expapi/verbs/scored",
                                           "http://adlnet.gov/expapi/verbs/passed",
                                           "http://adlnet.gov/expapi/verbs/failed"};
  std::set<std::string> ids;
  for (const auto& st : all) {
    ASSERT_TRUE(st.contains("id"));
    EXPECT_TRUE(is_uuid(st["id"].get<std::string>()));
    EXPECT_TRUE(ids.insert(st["id"]).second) << "duplicate statement id";
    // Opaque account actor, never a name or mbox.
    EXPECT_EQ(st["actor"]["objectType"], "Agent");
    EXPECT_EQ(st["actor"]["account"]["name"], "t1");
    EXPECT_FALSE(st["actor"]["account"]["homePage"].get<std::string>().empty());
    EXPECT_FALSE(st["actor"].contains("mbox"));
    EXPECT_TRUE(adl_verbs.count(st["verb"]["id"].get<std::string>())) << st["verb"]["id"];
    EXPECT_EQ(st["object"]["id"], "https://acdr.example/xapi/modules/m1");
    const auto& result = st["result"];
    const double scaled = result["score"]["scaled"];
    EXPECT_GE(scaled, 0.0);
    EXPECT_LE(scaled, 1.0);
    EXPECT_TRUE(result["success"].is_boolean());
    EXPECT_TRUE(std::regex_match(result["duration"].get<std::string>(), duration))
        << result["duration"];
    EXPECT_EQ(result["duration"], "PT12.345S");
    EXPECT_TRUE(is_uuid(st["context"]["registration"].get<std::string>()));
    EXPECT_EQ(st["context"]["revision"], "hash");
    EXPECT_EQ(st["context"]["platform"], "replay:demo.csv");
    EXPECT_TRUE(st["timestamp"].is_string());
  }
  // scored carries raw/min/max, completion and the metrics keyed by IRI.
  const auto& scored = all[0];
  EXPECT_EQ(verb_of(scored), "scored");
  EXPECT_EQ(scored["result"]["score"]["raw"], 82.5);
  EXPECT_EQ(scored["result"]["score"]["min"], 0);
  EXPECT_EQ(scored["result"]["score"]["max"], 100);
  EXPECT_DOUBLE_EQ(scored["result"]["score"]["scaled"].get<double>(), 0.825);
  EXPECT_EQ(scored["result"]["completion"], true);
  EXPECT_EQ(scored["result"]["extensions"]["https://acdr.example/xapi/metrics/"
                                           "nucleus_removed_fraction"],
            0.825);
  // passed/failed are cmi5 defined: categories and masteryScore, no completion.
  const auto& passed = all[1];
  EXPECT_EQ(verb_of(passed), "passed");
  EXPECT_FALSE(passed["result"].contains("completion"));
  EXPECT_EQ(passed["context"]["extensions"]
                  ["https://w3id.org/xapi/cmi5/context/extensions/masteryscore"],
            0.5);
  EXPECT_EQ(passed["context"]["contextActivities"]["category"][0]["id"],
            "https://w3id.org/xapi/cmi5/context/categories/cmi5");
  EXPECT_EQ(verb_of(all[3]), "failed");
  EXPECT_EQ(all[3]["result"]["success"], false);
}

TEST_F(XapiTest, OnlyOnePassedPerRegistration) {
  for (int i = 0; i < 3; ++i) add_attempt(db_, "t1", "m1", 70, true, minute(i));
  add_attempt(db_, "t1", "m1", 20, false, minute(3));
  add_attempt(db_, "t1", "m2", 70, true, minute(4));  // another registration
  const nlohmann::json all = statements();
  std::map<std::string, int> passed_per_registration;
  int scored = 0, failed = 0;
  for (const auto& st : all) {
    const std::string verb = verb_of(st);
    if (verb == "passed") ++passed_per_registration[st["context"]["registration"]];
    scored += verb == "scored";
    failed += verb == "failed";
  }
  EXPECT_EQ(scored, 5);
  EXPECT_EQ(failed, 1);
  ASSERT_EQ(passed_per_registration.size(), 2u);
  for (const auto& [registration, count] : passed_per_registration) EXPECT_EQ(count, 1);
}

TEST_F(XapiTest, PracticeRunningAndAbortedAttemptsAreNotExported) {
  add_attempt(db_, std::nullopt, "m1", 70, true, minute(0));
  AttemptStart s;
  s.trainee_id = "t1";
  s.module_id = "m1";
  const std::int64_t running = begin_attempt(db_, s).value();
  const std::int64_t quit = begin_attempt(db_, s).value();
  ASSERT_TRUE(abort_attempt(db_, quit, "quit").ok());
  EXPECT_TRUE(statements().empty());
  ASSERT_TRUE(finish_attempt(db_, running, test::make_outcome(60, true)).ok());
  EXPECT_EQ(statements().size(), 2u);
}

TEST_F(XapiTest, StatementIdsAreStableAcrossExports) {
  add_attempt(db_, "t1", "m1", 70, true, minute(0));
  const nlohmann::json a = statements();
  const nlohmann::json b = statements();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i]["id"], b[i]["id"]);
}

TEST_F(XapiTest, GateFailureAboveThePassLineDoesNotContradictMasteryScore) {
  AttemptStart s;
  s.trainee_id = "t1";
  s.module_id = "m1";
  const std::int64_t id = begin_attempt(db_, s).value();
  AttemptOutcome o = test::make_outcome(88.0, false);  // high score, failed by a safety gate
  o.score.reasons = {"vertebral artery breached (never-event)"};
  ASSERT_TRUE(finish_attempt(db_, id, o).ok());
  const nlohmann::json all = statements();
  ASSERT_EQ(all.size(), 2u);
  const auto& failed = all[1];
  EXPECT_EQ(verb_of(failed), "failed");
  EXPECT_EQ(failed["result"]["success"], false);
  EXPECT_FALSE(failed["context"]["extensions"].contains(
      "https://w3id.org/xapi/cmi5/context/extensions/masteryscore"));
  EXPECT_EQ(failed["result"]["extensions"]["https://acdr.example/xapi/extensions/fail-reasons"]
                [0],
            "vertebral artery breached (never-event)");
}

// What `acdr report --format xapi` exports is valid xAPI by Learning Locker's own validation
// package (tests/lrs/test_lrs.js --validate), for every kind of attempt we export: passed,
// failed, a repeated pass, a gate failure above the pass line, an instructor's override, a
// metric that is not a number.
TEST_F(XapiTest, StatementsPassLearningLockersValidation) {
  if (std::string missing = test_support::test_lrs_missing(ACDR_SOURCE_DIR); !missing.empty()) {
    GTEST_SKIP() << missing;
  }
  add_attempt(db_, "t1", "m1", 31.0, false, minute(0));
  add_attempt(db_, "t1", "m1", 82.5, true, minute(1));
  add_attempt(db_, "t1", "m1", 90.0, true, minute(2));
  AttemptStart s;
  s.trainee_id = "t2";
  s.module_id = "m2";
  s.override_lock = true;
  s.override_by = "dr-adams";
  s.override_reason = "reviewed the box module with the trainee";
  const std::int64_t id = begin_attempt(db_, s).value();
  AttemptOutcome o = test::make_outcome(88.0, false);
  o.score.reasons = {"vertebral artery breached (never-event)"};
  o.metrics.values.push_back({"zone_force_N", std::numeric_limits<double>::quiet_NaN()});
  ASSERT_TRUE(finish_attempt(db_, id, o).ok());
  const nlohmann::json all = statements();
  ASSERT_EQ(all.size(), 7u);

  const std::string file = dir_.file("statements.json");
  std::ofstream(file) << all.dump(2);
  const std::string output = dir_.file("validation.txt");
  const std::string command = "node '" + std::string(ACDR_SOURCE_DIR) +
                              "/tests/lrs/test_lrs.js' --validate '" + file + "' > '" + output +
                              "' 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(output);
  const std::string said(std::istreambuf_iterator<char>(in), {});
  EXPECT_EQ(status, 0) << said;
  EXPECT_NE(said.find("7 of 7 statements pass xapi-validation"), std::string::npos) << said;
}

TEST(XapiIri, IdsAndNamesArePercentEncoded) {
  XapiOptions o;
  o.base_iri = "https://lrs.hospital.example/acdr";  // no trailing slash
  EXPECT_EQ(xapi_activity_iri(o, "box warm-up/1"),
            "https://lrs.hospital.example/acdr/modules/box%20warm-up%2F1");
  EXPECT_EQ(xapi_metric_iri(o, "peak_force_N"),
            "https://lrs.hospital.example/acdr/metrics/peak_force_N");
}

}  // namespace
}  // namespace acdr
