// Tests of cli/send_command.cpp: what `acdr send` prints and its exit codes, with the LRS
// configured by a file, against the test LRS on 127.0.0.1 (tests/lrs).
#include "cli/send_command.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/stat.h>

#include <fstream>
#include <sstream>

#include "db/outbox.hpp"
#include "tests/db/db_test_support.hpp"
#include "tests/support/test_lrs_process.hpp"

namespace acdr {
namespace {

using test_support::LrsProcess;

class SendCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* name :
         {"ACDR_LRS_CONFIG", "ACDR_LRS_ENDPOINT", "ACDR_LRS_KEY", "ACDR_LRS_SECRET",
          "ACDR_XAPI_IRI_BASE", "ACDR_LRS_SEND_AFTER_ATTEMPT"}) {
      unsetenv(name);
    }
    setenv("XDG_CONFIG_HOME", dir_.file("config").c_str(), 1);  // no user file applies
    db_path_ = dir_.file("record.sqlite");
    Database db = test::open_or_fail(db_path_);
    test::register_curriculum(db, 1);
    test::add_attempt(db, "t-1", "m1", 35.0, false, test::minute(1));
    test::add_attempt(db, "t-1", "m1", 75.0, true, test::minute(2));
  }
  // A configuration file (mode 0600, as a file with a secret must be).
  std::string config(const std::string& endpoint, const std::string& secret = "s3cret",
                     const std::string& extra = "") {
    const std::string path = dir_.file("lrs.json");
    std::ofstream(path) << R"({"endpoint": ")" << endpoint
                        << R"(", "key": "acdr-station", "secret": ")" << secret << '"' << extra
                        << "}";
    chmod(path.c_str(), 0600);
    return path;
  }
  LrsProcess start() {
    test_support::TestLrsOptions o;
    o.source_dir = ACDR_SOURCE_DIR;
    o.store = dir_.file("lrs.jsonl");
    std::string error;
    LrsProcess p = LrsProcess::start_test_lrs(o, &error);
    EXPECT_TRUE(p.running()) << error;
    return p;
  }
  OutboxCounts counts() {
    Database db = test::open_or_fail(db_path_);
    return outbox_counts(db).value();
  }

  test::TempDir dir_;
  std::string db_path_;
};

TEST_F(SendCommandTest, WithoutAnEndpointItSaysSoAndKeepsTheQueue) {
  SendOptions options;
  options.db_path = db_path_;
  std::ostringstream out, err;
  EXPECT_EQ(run_send(options, out, err), 1);
  EXPECT_NE(err.str().find("no LRS endpoint is configured"), std::string::npos) << err.str();
  EXPECT_NE(err.str().find("ACDR_LRS_ENDPOINT"), std::string::npos) << err.str();
  EXPECT_EQ(counts().queued, 4);
}

TEST_F(SendCommandTest, AMissingRecordIsNotCreated) {
  SendOptions options;
  options.db_path = dir_.file("typo.sqlite");
  std::ostringstream out, err;
  EXPECT_EQ(run_send(options, out, err), 1);
  EXPECT_NE(err.str().find("typo.sqlite"), std::string::npos) << err.str();
  EXPECT_FALSE(std::filesystem::exists(options.db_path));
}

TEST_F(SendCommandTest, SendsTheOutboxOnceAndAfterAnOutage) {
  if (std::string missing = test_support::test_lrs_missing(ACDR_SOURCE_DIR); !missing.empty()) {
    GTEST_SKIP() << missing;
  }
  LrsProcess lrs = start();
  const std::string endpoint = lrs.endpoint();
  SendOptions options;
  options.db_path = db_path_;
  options.config = config(endpoint);
  options.retry_for_s = 0.5;

  // Down: the statements stay queued, exit 3, and the message says what to do.
  lrs.kill_now();
  {
    std::ostringstream out, err;
    EXPECT_EQ(run_send(options, out, err), 3) << err.str();
    EXPECT_NE(out.str().find("0 stored"), std::string::npos) << out.str();
    EXPECT_NE(out.str().find("run acdr send again"), std::string::npos) << out.str();
    EXPECT_EQ(counts().queued, 4);
  }
  // Up again (a new port): all four go, each once.
  LrsProcess again = start();
  options.config = config(again.endpoint());
  {
    std::ostringstream out, err;
    EXPECT_EQ(run_send(options, out, err), 0) << err.str();
    EXPECT_NE(out.str().find("4 stored, 0 already stored, 0 refused"), std::string::npos)
        << out.str();
    EXPECT_NE(out.str().find("0 queued, 4 sent, 0 failed"), std::string::npos) << out.str();
  }
  EXPECT_EQ(test_support::stored_ids(dir_.file("lrs.jsonl")).size(), 4u);
  // Nothing left: a second run sends nothing.
  std::ostringstream out, err;
  EXPECT_EQ(run_send(options, out, err), 0);
  EXPECT_NE(out.str().find("0 stored"), std::string::npos) << out.str();
  EXPECT_EQ(test_support::stored_ids(dir_.file("lrs.jsonl")).size(), 4u);
}

TEST_F(SendCommandTest, WrongCredentialsAreAClearErrorAndNothingIsMarkedSent) {
  if (std::string missing = test_support::test_lrs_missing(ACDR_SOURCE_DIR); !missing.empty()) {
    GTEST_SKIP() << missing;
  }
  LrsProcess lrs = start();
  SendOptions options;
  options.db_path = db_path_;
  options.config = config(lrs.endpoint(), "wrong-secret");
  std::ostringstream out, err;
  EXPECT_EQ(run_send(options, out, err), 1);
  EXPECT_NE(err.str().find("refused the credentials (HTTP 401"), std::string::npos) << err.str();
  EXPECT_NE(err.str().find("check the LRS key and secret"), std::string::npos) << err.str();
  EXPECT_EQ(err.str().find("wrong-secret"), std::string::npos) << "the secret is not printed";
  EXPECT_EQ(counts().sent, 0);
  EXPECT_EQ(counts().queued, 4);
}

TEST_F(SendCommandTest, QueueExistingQueuesOlderAttemptsWithTheConfiguredIriBase) {
  {
    Database db = test::open_or_fail(db_path_);
    ASSERT_TRUE(db.exec("DELETE FROM xapi_outbox").ok());  // a record from before the outbox
  }
  SendOptions options;
  options.db_path = db_path_;
  options.config = config("http://127.0.0.1:1/xapi/", "s3cret",
                          R"(, "activity_iri_base": "https://training.example.org/acdr/")");
  options.queue_existing = true;
  options.retry_for_s = 0.0;
  std::ostringstream out, err;
  EXPECT_EQ(run_send(options, out, err), 3);  // nothing listens on port 1
  EXPECT_NE(out.str().find("queued 4 statements"), std::string::npos) << out.str();
  Database db = test::open_or_fail(db_path_);
  for (const OutboxItem& item : list_outbox(db).value()) {
    EXPECT_NE(item.statement.find("https://training.example.org/acdr/modules/m1"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace acdr
