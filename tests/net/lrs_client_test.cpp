// Tests of net/lrs_client.cpp: how each answer of a store is sorted (the table in
// lrs_client.hpp), and a PUT to a real statements endpoint: stored, then the same again.
#include "net/lrs_client.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "tests/support/test_lrs_process.hpp"

namespace acdr {
namespace {

HttpResponse answer(long status, const std::string& body = "") {
  HttpResponse r;
  r.answered = true;
  r.status = status;
  r.body = body;
  return r;
}

TEST(LrsClient, AnswersAreSortedByWhatTheSenderMustDo) {
  const std::string url = "http://127.0.0.1:9/xapi/statements";
  EXPECT_EQ(classify_lrs_response(answer(204), url).answer, LrsAnswer::kStored);
  EXPECT_EQ(classify_lrs_response(answer(200), url).answer, LrsAnswer::kStored);
  EXPECT_EQ(classify_lrs_response(answer(409), url).answer, LrsAnswer::kAlreadyStored);
  for (long s : {408L, 425L, 429L, 500L, 502L, 503L}) {
    EXPECT_EQ(classify_lrs_response(answer(s), url).answer, LrsAnswer::kTryLater) << s;
  }
  HttpResponse none;
  none.error = "Connection refused";
  const LrsReply down = classify_lrs_response(none, url);
  EXPECT_EQ(down.answer, LrsAnswer::kTryLater);
  EXPECT_NE(down.message.find("Connection refused"), std::string::npos);
  for (long s : {401L, 403L, 404L, 405L, 301L}) {
    EXPECT_EQ(classify_lrs_response(answer(s), url).answer, LrsAnswer::kConfigProblem) << s;
  }
  const LrsReply bad =
      classify_lrs_response(answer(400, R"({"message": "invalid", "warnings": ["actor"]})"), url);
  EXPECT_EQ(bad.answer, LrsAnswer::kRejected);
  EXPECT_NE(bad.message.find("HTTP 400: invalid [\"actor\"]"), std::string::npos) << bad.message;
  const LrsReply login = classify_lrs_response(answer(401, "Unauthorized\n"), url);
  EXPECT_NE(login.message.find("credentials"), std::string::npos) << login.message;
  EXPECT_NE(login.message.find("HTTP 401: Unauthorized"), std::string::npos) << login.message;
  // A long answer is cut, on one line.
  const LrsReply huge = classify_lrs_response(answer(413, std::string(5000, 'x') + "\n"), url);
  EXPECT_LT(huge.message.size(), 800u);
  EXPECT_EQ(huge.message.find('\n'), std::string::npos);
}

TEST(LrsClient, PutStoresAStatementAndARepeatIsHarmless) {
  if (std::string missing = test_support::test_lrs_missing(ACDR_SOURCE_DIR); !missing.empty()) {
    GTEST_SKIP() << missing;
  }
  const std::string store = (std::filesystem::temp_directory_path() /
                             ("acdr-lrs-client-" + std::to_string(getpid()) + ".jsonl"))
                                .string();
  std::filesystem::remove(store);
  std::filesystem::remove(store + ".log");
  test_support::TestLrsOptions options;
  options.source_dir = ACDR_SOURCE_DIR;
  options.store = store;
  std::string error;
  test_support::LrsProcess lrs = test_support::LrsProcess::start_test_lrs(options, &error);
  ASSERT_TRUE(lrs.running()) << error;

  LrsConfig config;
  config.endpoint = lrs.endpoint();
  config.key = options.key;
  config.secret = options.secret;
  LrsClient client(config);
  const std::string id = "0f0a2b8e-5d41-5c1b-9f0a-2b7e6d9c4a14";
  const std::string statement =
      R"({"id": ")" + id +
      R"(", "actor": {"objectType": "Agent", "account": {"homePage": "https://acdr.example/trainees", "name": "t-1"}},
          "verb": {"id": "http://adlnet.gov/expapi/verbs/scored", "display": {"en-US": "scored"}},
          "object": {"objectType": "Activity", "id": "https://acdr.example/xapi/modules/m1"}})";
  EXPECT_EQ(client.put_statement(id, statement).answer, LrsAnswer::kStored);
  EXPECT_EQ(client.put_statement(id, statement).answer, LrsAnswer::kStored);  // same: 204
  std::string changed = statement;
  changed.replace(changed.find("t-1"), 3, "t-2");
  EXPECT_EQ(client.put_statement(id, changed).answer, LrsAnswer::kAlreadyStored);  // 409
  const LrsReply invalid = client.put_statement(id, R"({"actor": {}})");
  EXPECT_EQ(invalid.answer, LrsAnswer::kRejected);
  EXPECT_NE(invalid.message.find("not valid xAPI"), std::string::npos) << invalid.message;

  EXPECT_EQ(test_support::stored_ids(store), std::vector<std::string>{id});
  const auto outcomes = test_support::logged_outcomes(store);
  EXPECT_EQ(outcomes.at(id).at("stored"), 1);
  EXPECT_EQ(outcomes.at(id).at("same"), 1);
  EXPECT_EQ(outcomes.at(id).at("conflict"), 1);
  lrs.kill_now();
  for (const char* ext : {"", ".log", ".stderr", ".stdout"}) std::filesystem::remove(store + ext);
}

}  // namespace
}  // namespace acdr
