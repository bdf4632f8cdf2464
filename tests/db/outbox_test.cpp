// Tests of db/outbox.cpp: finishing an attempt queues its statements in the same transaction,
// exactly those of the export; queueing is idempotent by statement id; the states a sender
// moves a statement through.
#include "db/outbox.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "db/report.hpp"
#include "tests/db/db_test_support.hpp"

namespace acdr {
namespace {

using test::add_attempt;
using test::minute;

class OutboxTest : public ::testing::Test {
 protected:
  void SetUp() override {
    db_ = test::open_or_fail(dir_.file("record.sqlite"));
    test::register_curriculum(db_, 2);
  }
  std::vector<OutboxItem> outbox(std::optional<OutboxState> state = std::nullopt) {
    DbResult<std::vector<OutboxItem>> items = list_outbox(db_, state);
    EXPECT_TRUE(items.ok()) << items.error().message;
    return items.ok() ? items.value() : std::vector<OutboxItem>{};
  }
  // The export's statements by id (acdr report --format xapi).
  std::map<std::string, nlohmann::json> exported() {
    ReportRequest r;
    r.format = ReportFormat::kXapi;
    std::ostringstream out;
    EXPECT_TRUE(write_report(db_, r, out).ok());
    std::map<std::string, nlohmann::json> by_id;
    for (const nlohmann::json& st : nlohmann::json::parse(out.str())) by_id[st["id"]] = st;
    return by_id;
  }
  std::int64_t count_rows(const char* sql) {
    DbResult<Statement> s = db_.prepare(sql);
    EXPECT_TRUE(s.ok());
    EXPECT_TRUE(s->step().ok());
    return s->column_int64(0);
  }

  test::TempDir dir_;
  Database db_;
};

TEST_F(OutboxTest, FinishingATraineeAttemptQueuesExactlyItsExportedStatements) {
  add_attempt(db_, "t-1", "m1", 40.0, false, minute(1));  // scored + failed
  add_attempt(db_, "t-1", "m1", 80.0, true, minute(2));   // scored + passed
  add_attempt(db_, "t-1", "m1", 90.0, true, minute(3));   // scored (one passed per registration)
  add_attempt(db_, "t-2", "m1", 70.0, true, minute(4));   // scored + passed
  add_attempt(db_, std::nullopt, "m1", 95.0, true, minute(5));  // practice: nothing

  const std::vector<OutboxItem> items = outbox();
  const std::map<std::string, nlohmann::json> export_by_id = exported();
  ASSERT_EQ(items.size(), 7u);
  ASSERT_EQ(export_by_id.size(), 7u);
  for (const OutboxItem& item : items) {
    EXPECT_EQ(item.state, OutboxState::kQueued);
    EXPECT_EQ(item.tries, 0);
    const auto it = export_by_id.find(item.statement_id);
    ASSERT_NE(it, export_by_id.end()) << item.statement_id << " is queued but not exported";
    // The very statement the export gives, and the outbox id orders it after the ones before.
    EXPECT_EQ(nlohmann::json::parse(item.statement), it->second) << item.statement_id;
  }
  EXPECT_LT(items.front().attempt_id, items.back().attempt_id);
}

TEST_F(OutboxTest, RunningAndAbortedAttemptsQueueNothing) {
  AttemptStart start;
  start.trainee_id = "t-1";
  start.module_id = "m1";
  DbResult<std::int64_t> running = begin_attempt(db_, start);
  ASSERT_TRUE(running.ok());
  DbResult<std::int64_t> aborted = begin_attempt(db_, start);
  ASSERT_TRUE(aborted.ok());
  ASSERT_TRUE(abort_attempt(db_, aborted.value(), "stopped").ok());
  EXPECT_TRUE(outbox().empty());
  DbResult<int> none = queue_attempt_statements(db_, running.value(), {});
  ASSERT_TRUE(none.ok()) << none.error().message;
  EXPECT_EQ(none.value(), 0);
}

TEST_F(OutboxTest, TheStatementsAreStoredWithTheAttemptOrNotAtAll) {
  AttemptStart start;
  start.trainee_id = "t-1";
  start.module_id = "m1";
  DbResult<std::int64_t> id = begin_attempt(db_, start);
  ASSERT_TRUE(id.ok());
  // An outbox that refuses rows: finishing fails as a whole, the attempt stays running.
  ASSERT_TRUE(db_.exec("CREATE TEMP TRIGGER refuse BEFORE INSERT ON xapi_outbox "
                       "BEGIN SELECT RAISE(ABORT, 'outbox refused'); END")
                  .ok());
  DbStatus finished = finish_attempt(db_, id.value(), test::make_outcome(70.0, true));
  ASSERT_FALSE(finished.ok());
  EXPECT_NE(finished.error().message.find("outbox refused"), std::string::npos)
      << finished.error().message;
  EXPECT_EQ(count_rows("SELECT count(*) FROM attempts WHERE status = 'running'"), 1);
  EXPECT_EQ(count_rows("SELECT count(*) FROM metrics"), 0);
  ASSERT_TRUE(db_.exec("DROP TRIGGER temp.refuse").ok());
  ASSERT_TRUE(finish_attempt(db_, id.value(), test::make_outcome(70.0, true)).ok());
  EXPECT_EQ(outbox().size(), 2u);
}

TEST_F(OutboxTest, QueueingIsIdempotentByStatementId) {
  const std::int64_t a = add_attempt(db_, "t-1", "m1", 70.0, true, minute(1));
  add_attempt(db_, "t-1", "m1", 30.0, false, minute(2));
  ASSERT_EQ(outbox().size(), 4u);
  DbResult<int> again = queue_attempt_statements(db_, a, {});
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again.value(), 0);
  DbResult<int> all = queue_all_statements(db_, {});
  ASSERT_TRUE(all.ok());
  EXPECT_EQ(all.value(), 0);
  // A record from before the outbox: its attempts are queued on request, once.
  ASSERT_TRUE(db_.exec("DELETE FROM xapi_outbox").ok());
  all = queue_all_statements(db_, {});
  ASSERT_TRUE(all.ok()) << all.error().message;
  EXPECT_EQ(all.value(), 4);
  EXPECT_EQ(outbox().size(), 4u);
}

TEST_F(OutboxTest, QueuedStatementsCarryTheConfiguredIriBase) {
  AttemptStart start;
  start.trainee_id = "t-1";
  start.module_id = "m1";
  DbResult<std::int64_t> id = begin_attempt(db_, start);
  ASSERT_TRUE(id.ok());
  XapiOptions xapi;
  xapi.base_iri = "https://training.example.org/acdr/";
  ASSERT_TRUE(finish_attempt(db_, id.value(), test::make_outcome(70.0, true), xapi).ok());
  for (const OutboxItem& item : outbox()) {
    const nlohmann::json st = nlohmann::json::parse(item.statement);
    EXPECT_EQ(st["object"]["id"], "https://training.example.org/acdr/modules/m1");
  }
}

TEST_F(OutboxTest, ASenderMovesStatementsThroughTheirStates) {
  add_attempt(db_, "t-1", "m1", 70.0, true, minute(1));
  add_attempt(db_, "t-1", "m1", 30.0, false, minute(2));
  DbResult<std::vector<OutboxItem>> first = queued_statements(db_, 3);
  ASSERT_TRUE(first.ok());
  ASSERT_EQ(first->size(), 3u);
  const std::vector<OutboxItem>& q = first.value();
  EXPECT_LT(q[0].id, q[1].id);

  ASSERT_TRUE(note_statement_try(db_, q[0].id, "no answer from the store").ok());
  ASSERT_TRUE(mark_statement_sent(db_, q[0].id, "http://127.0.0.1:1/xapi/").ok());
  // Marking sent again (another sender got there first) is not an error.
  EXPECT_TRUE(mark_statement_sent(db_, q[0].id, "http://127.0.0.1:1/xapi/").ok());
  ASSERT_TRUE(mark_statement_failed(db_, q[1].id, "HTTP 400: bad statement").ok());
  ASSERT_TRUE(note_statement_try(db_, q[2].id, "HTTP 503").ok());

  const std::vector<OutboxItem> sent = outbox(OutboxState::kSent);
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].tries, 2);
  EXPECT_TRUE(sent[0].sent_utc.has_value());
  EXPECT_EQ(sent[0].sent_to, "http://127.0.0.1:1/xapi/");
  const std::vector<OutboxItem> failed = outbox(OutboxState::kFailed);
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed[0].last_error, "HTTP 400: bad statement");
  // A failed or sent statement is no longer handed out; a retried one still is.
  DbResult<std::vector<OutboxItem>> next = queued_statements(db_, 10);
  ASSERT_TRUE(next.ok());
  ASSERT_EQ(next->size(), 2u);
  EXPECT_EQ(next->front().id, q[2].id);
  EXPECT_EQ(next->front().tries, 1);
  EXPECT_FALSE(mark_statement_failed(db_, q[0].id, "late").ok());

  DbResult<OutboxCounts> counts = outbox_counts(db_);
  ASSERT_TRUE(counts.ok());
  EXPECT_EQ(counts->queued, 2);
  EXPECT_EQ(counts->sent, 1);
  EXPECT_EQ(counts->failed, 1);
  DbResult<int> requeued = requeue_failed_statements(db_);
  ASSERT_TRUE(requeued.ok());
  EXPECT_EQ(requeued.value(), 1);
  EXPECT_EQ(outbox_counts(db_)->queued, 3);
}

}  // namespace
}  // namespace acdr
