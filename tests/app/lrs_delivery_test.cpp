// Tests of app/lrs_delivery.cpp against real stores on 127.0.0.1: the validating test LRS
// (tests/lrs/test_lrs.js: Learning Locker's xapi-validation on every statement, statements kept
// in a file so it can be killed and restarted) and Learning Locker's statements service. Every
// statement arrives once, also when the store goes down in mid-queue; wrong credentials mark
// nothing sent; a statement the store refuses is kept as failed with its answer.
#include "app/lrs_delivery.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <future>
#include <nlohmann/json.hpp>
#include <set>

#include "net/http_client.hpp"
#include "tests/db/db_test_support.hpp"
#include "tests/support/test_lrs_process.hpp"

namespace acdr {
namespace {

using test::add_attempt;
using test::minute;
using test_support::LrsProcess;

class LrsDeliveryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::string missing = test_support::test_lrs_missing(ACDR_SOURCE_DIR); !missing.empty()) {
      GTEST_SKIP() << missing;
    }
    db_ = test::open_or_fail(dir_.file("record.sqlite"));
    test::register_curriculum(db_, 2);
    // Three trainees, both modules, passes and fails: 2 statements per attempt except a
    // repeated pass in a registration (scored only).
    int m = 0;
    for (const char* trainee : {"t-1", "t-2", "t-3"}) {
      add_attempt(db_, trainee, "m1", 35.0, false, minute(++m));
      add_attempt(db_, trainee, "m1", 72.0, true, minute(++m));
      add_attempt(db_, trainee, "m1", 81.0, true, minute(++m));
      add_attempt(db_, trainee, "m2", 64.0, true, minute(++m));
    }
    add_attempt(db_, std::nullopt, "m1", 90.0, true, minute(++m));  // practice: not sent
    DbResult<std::vector<OutboxItem>> items = list_outbox(db_);
    ASSERT_TRUE(items.ok());
    for (const OutboxItem& item : items.value()) queued_ids_.push_back(item.statement_id);
    ASSERT_EQ(queued_ids_.size(), 21u);
    options_.source_dir = ACDR_SOURCE_DIR;
    options_.store = dir_.file("lrs.jsonl");
  }

  LrsProcess start(int exit_after = 0, int port = 0) {
    test_support::TestLrsOptions o = options_;
    o.exit_after = exit_after;
    o.port = port;
    std::string error;
    LrsProcess p = LrsProcess::start_test_lrs(o, &error);
    EXPECT_TRUE(p.running()) << error;
    return p;
  }
  LrsConfig config_for(const LrsProcess& lrs) const {
    LrsConfig c;
    c.endpoint = lrs.endpoint();
    c.key = options_.key;
    c.secret = options_.secret;
    c.timeout_s = 10.0;
    return c;
  }
  OutboxCounts counts() {
    DbResult<OutboxCounts> c = outbox_counts(db_);
    EXPECT_TRUE(c.ok());
    return c.ok() ? c.value() : OutboxCounts{};
  }
  // Each queued statement is in the store exactly once, and nothing else is.
  void expect_each_stored_once() {
    const std::vector<std::string> stored = test_support::stored_ids(options_.store);
    EXPECT_EQ(stored.size(), queued_ids_.size());
    EXPECT_EQ(std::multiset<std::string>(stored.begin(), stored.end()),
              std::multiset<std::string>(queued_ids_.begin(), queued_ids_.end()));
  }

  test::TempDir dir_;
  Database db_;
  std::vector<std::string> queued_ids_;
  test_support::TestLrsOptions options_;
};

TEST_F(LrsDeliveryTest, EveryStatementArrivesOnceAndValidates) {
  LrsProcess lrs = start();
  const DeliveryReport report = deliver_outbox(db_, config_for(lrs));
  EXPECT_TRUE(report.emptied()) << report.stopped << report.record_error;
  EXPECT_EQ(report.stored, 21);
  EXPECT_EQ(report.already_stored, 0);
  EXPECT_EQ(report.rejected, 0) << (report.rejections.empty() ? "" : report.rejections[0]);
  EXPECT_EQ(report.left.sent, 21);
  EXPECT_EQ(report.left.queued, 0);
  expect_each_stored_once();
  // One PUT per statement: none sent twice, none found invalid by xapi-validation.
  for (const auto& [id, outcomes] : test_support::logged_outcomes(options_.store)) {
    EXPECT_EQ(outcomes, (std::map<std::string, int>{{"stored", 1}})) << id;
  }
  // Sending again has nothing to send.
  const DeliveryReport again = deliver_outbox(db_, config_for(lrs));
  EXPECT_EQ(again.stored + again.already_stored, 0);
  EXPECT_EQ(test_support::logged_outcomes(options_.store).size(), 21u);
}

TEST_F(LrsDeliveryTest, AStoreThatDiesInMidQueueLosesNothingAndDuplicatesNothing) {
  // The store takes 8 statements, stores the 8th but dies before answering it.
  LrsProcess lrs = start(/*exit_after=*/8);
  DeliveryOptions quick;
  quick.retry_for_s = 1.0;
  quick.first_backoff_s = 0.2;
  const LrsConfig config = config_for(lrs);
  const DeliveryReport down = deliver_outbox(db_, config, quick);
  EXPECT_TRUE(lrs.wait_exit(5.0));
  EXPECT_FALSE(down.emptied());
  EXPECT_FALSE(down.config_problem);
  EXPECT_NE(down.stopped.find("no answer"), std::string::npos) << down.stopped;
  EXPECT_GE(down.failed_tries, 2);  // the first try and at least one after a pause
  EXPECT_EQ(down.stored, 7);        // the 8th was stored but never acknowledged
  EXPECT_EQ(counts().sent, 7);
  EXPECT_EQ(counts().queued, 14);
  EXPECT_EQ(test_support::stored_ids(options_.store).size(), 8u);

  // Back up (same store file): the rest goes, the unacknowledged one is recognised.
  LrsProcess again = start();
  const DeliveryReport up = deliver_outbox(db_, config_for(again));
  EXPECT_TRUE(up.emptied()) << up.stopped;
  EXPECT_EQ(up.stored, 14);  // the 8th answered 204 (identical) + 13 new
  EXPECT_EQ(counts().sent, 21);
  EXPECT_EQ(counts().queued, 0);
  expect_each_stored_once();
  const auto outcomes = test_support::logged_outcomes(options_.store);
  int repeats = 0;
  for (const auto& [id, o] : outcomes) {
    EXPECT_EQ(o.count("conflict"), 0u) << id;
    EXPECT_EQ(o.count("invalid"), 0u) << id;
    if (o.count("same")) {
      ++repeats;
      EXPECT_EQ(o.at("dropped"), 1) << id;  // the in-flight one, and only it
    }
  }
  EXPECT_EQ(repeats, 1);
}

TEST_F(LrsDeliveryTest, BackingOffRidesOutARestartInOneRun) {
  LrsProcess first = start(/*exit_after=*/5);
  const int port = first.port();
  DeliveryOptions patient;
  patient.retry_for_s = 60.0;
  patient.first_backoff_s = 0.25;
  patient.max_backoff_s = 2.0;
  const LrsConfig config = config_for(first);
  // The sender runs on its own connection while the store dies and comes back on its port.
  std::future<DeliveryReport> sending = std::async(std::launch::async, [&] {
    Database own = test::open_or_fail(dir_.file("record.sqlite"));
    return deliver_outbox(own, config, patient);
  });
  ASSERT_TRUE(first.wait_exit(30.0));
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // down for a while
  LrsProcess second = start(0, port);
  const DeliveryReport report = sending.get();
  EXPECT_TRUE(report.emptied()) << report.stopped;
  EXPECT_GE(report.failed_tries, 2);
  EXPECT_EQ(report.stored, 21);  // 4 acknowledged, the 5th and the rest after the restart
  expect_each_stored_once();
}

TEST_F(LrsDeliveryTest, WrongCredentialsStopWithAClearErrorAndMarkNothingSent) {
  LrsProcess lrs = start();
  LrsConfig config = config_for(lrs);
  config.secret = "not-the-secret";
  const DeliveryReport report = deliver_outbox(db_, config);
  EXPECT_TRUE(report.config_problem);
  EXPECT_NE(report.stopped.find("refused the credentials"), std::string::npos) << report.stopped;
  EXPECT_NE(report.stopped.find("HTTP 401"), std::string::npos) << report.stopped;
  EXPECT_EQ(report.stored, 0);
  EXPECT_EQ(counts().sent, 0);
  EXPECT_EQ(counts().failed, 0);
  EXPECT_EQ(counts().queued, 21);
  EXPECT_TRUE(test_support::stored_ids(options_.store).empty());
  // The secret never reaches the record.
  db_ = Database();
  for (const char* ext : {"", "-wal"}) {
    std::ifstream in(dir_.file("record.sqlite") + ext, std::ios::binary);
    const std::string bytes(std::istreambuf_iterator<char>(in), {});
    EXPECT_EQ(bytes.find("not-the-secret"), std::string::npos);
    EXPECT_EQ(bytes.find(options_.secret), std::string::npos);
  }
}

TEST_F(LrsDeliveryTest, AStatementTheStoreRefusesIsKeptAsFailedAndTheRestGo) {
  // A statement no store accepts (an actor without an identifier), queued by hand.
  DbResult<Statement> s = db_.prepare(
      "INSERT INTO xapi_outbox (statement_id, attempt_id, statement, queued_utc) "
      "VALUES ('11111111-2222-5333-8444-555555555555', 1, "
      "'{\"id\": \"11111111-2222-5333-8444-555555555555\", \"actor\": {\"objectType\": "
      "\"Agent\"}, \"verb\": {\"id\": \"http://adlnet.gov/expapi/verbs/scored\"}, "
      "\"object\": {\"id\": \"https://acdr.example/xapi/modules/m1\"}}', "
      "'2024-05-01T10:00:00.000Z')");
  ASSERT_TRUE(s.ok());
  ASSERT_TRUE(s->run().ok());
  LrsProcess lrs = start();
  const DeliveryReport report = deliver_outbox(db_, config_for(lrs));
  EXPECT_TRUE(report.emptied());
  EXPECT_EQ(report.stored, 21);
  EXPECT_EQ(report.rejected, 1);
  ASSERT_EQ(report.rejections.size(), 1u);
  EXPECT_NE(report.rejections[0].find("HTTP 400"), std::string::npos) << report.rejections[0];
  DbResult<std::vector<OutboxItem>> failed = list_outbox(db_, OutboxState::kFailed);
  ASSERT_TRUE(failed.ok());
  ASSERT_EQ(failed->size(), 1u);
  EXPECT_NE(failed->front().last_error.find("not valid xAPI"), std::string::npos)
      << failed->front().last_error;
  expect_each_stored_once();
}

TEST_F(LrsDeliveryTest, NothingIsLostWhileNoStoreListens) {
  // A store that is not there at all: every statement stays queued, with the try noted.
  LrsProcess lrs = start();
  const LrsConfig config = config_for(lrs);
  lrs.kill_now();
  DeliveryOptions once;
  once.retry_for_s = 0.0;
  const DeliveryReport report = deliver_outbox(db_, config, once);
  EXPECT_FALSE(report.emptied());
  EXPECT_EQ(report.failed_tries, 1);
  EXPECT_EQ(counts().queued, 21);
  DbResult<std::vector<OutboxItem>> first = queued_statements(db_, 1);
  ASSERT_TRUE(first.ok());
  EXPECT_EQ(first->front().tries, 1);
  EXPECT_NE(first->front().last_error.find("no answer"), std::string::npos);
}

// Learning Locker's own statements service (xapi-statements from npm, its statements in
// memory): a real LRS implementation that validates, stores and answers repeats by id.
TEST_F(LrsDeliveryTest, LearningLockersStatementsServiceGetsEveryStatementOnce) {
  std::string error;
  LrsProcess lrs = LrsProcess::start_learning_locker(ACDR_SOURCE_DIR, &error);
  ASSERT_TRUE(lrs.running()) << error;
  LrsConfig config = config_for(lrs);
  config.timeout_s = 30.0;
  DeliveryReport report = deliver_outbox(db_, config);
  EXPECT_TRUE(report.emptied()) << report.stopped
                                << (report.rejections.empty() ? "" : report.rejections[0]);
  EXPECT_EQ(report.stored, 21);

  // As if every answer had been lost: all queued again and sent again.
  ASSERT_TRUE(db_.exec("UPDATE xapi_outbox SET state = 'queued'").ok());
  report = deliver_outbox(db_, config);
  EXPECT_TRUE(report.emptied()) << report.stopped;
  EXPECT_EQ(report.stored + report.already_stored, 21);

  HttpClient http;
  HttpRequest get;
  get.url = lrs.endpoint() + "statements?limit=100";
  get.headers = {{"X-Experience-API-Version", "1.0.3"}};
  get.user = config.key;
  get.password = config.secret;
  const HttpResponse response = http.send(get);
  ASSERT_TRUE(response.answered) << response.error;
  ASSERT_EQ(response.status, 200) << response.body;
  const nlohmann::json body = nlohmann::json::parse(response.body);
  ASSERT_EQ(body["more"], "") << "all statements in one page";
  std::multiset<std::string> held;
  for (const nlohmann::json& st : body["statements"]) {
    held.insert(st["id"].get<std::string>());
  }
  EXPECT_EQ(held, std::multiset<std::string>(queued_ids_.begin(), queued_ids_.end()));
}

}  // namespace
}  // namespace acdr
