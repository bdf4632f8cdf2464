// Tests of net/http_client.cpp: a refused connection is an unanswered response, not an
// exception; a round trip to a real server on 127.0.0.1 carries method, headers, body and
// Basic authentication.
#include "net/http_client.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "tests/support/test_lrs_process.hpp"

namespace acdr {
namespace {

TEST(HttpClient, ARefusedConnectionIsUnanswered) {
  HttpClient client;
  HttpRequest request;
  request.url = "http://127.0.0.1:1/xapi/about";  // port 1: nothing listens (tcpmux)
  request.connect_timeout_s = 2.0;
  const HttpResponse response = client.send(request);
  EXPECT_FALSE(response.answered);
  EXPECT_EQ(response.status, 0);
  EXPECT_FALSE(response.error.empty());
}

TEST(HttpClient, RoundTripWithBasicAuthentication) {
  if (std::string missing = test_support::test_lrs_missing(ACDR_SOURCE_DIR); !missing.empty()) {
    GTEST_SKIP() << missing;
  }
  const std::string store = (std::filesystem::temp_directory_path() /
                             ("acdr-http-" + std::to_string(getpid()) + ".jsonl"))
                                .string();
  std::filesystem::remove(store);
  test_support::TestLrsOptions options;
  options.source_dir = ACDR_SOURCE_DIR;
  options.store = store;
  std::string error;
  test_support::LrsProcess lrs = test_support::LrsProcess::start_test_lrs(options, &error);
  ASSERT_TRUE(lrs.running()) << error;

  HttpClient client;
  HttpRequest request;
  request.url = lrs.endpoint() + "statements";
  request.headers = {{"X-Experience-API-Version", "1.0.3"}};
  request.user = options.key;
  request.password = options.secret;
  HttpResponse ok = client.send(request);
  ASSERT_TRUE(ok.answered) << ok.error;
  EXPECT_EQ(ok.status, 200);
  EXPECT_EQ(ok.header("x-experience-api-version"), "1.0.3");
  EXPECT_TRUE(nlohmann::json::parse(ok.body).contains("statements"));

  request.password = "wrong";
  const HttpResponse refused = client.send(request);  // the same connection, kept open
  ASSERT_TRUE(refused.answered);
  EXPECT_EQ(refused.status, 401);

  request.method = "PUT";
  request.password = options.secret;
  request.url += "?statementId=5d3c8f0e-8a41-4c1b-9f0a-2b7e6d9c4a14";
  request.body = "{not json";
  const HttpResponse bad = client.send(request);
  ASSERT_TRUE(bad.answered);
  EXPECT_EQ(bad.status, 400);
  EXPECT_NE(bad.body.find("not JSON"), std::string::npos) << bad.body;
  lrs.kill_now();
  std::filesystem::remove(store);
  std::filesystem::remove(store + ".log");
  std::filesystem::remove(store + ".stderr");
  std::filesystem::remove(store + ".stdout");
}

TEST(UrlEscape, LeavesUnreservedCharactersAndEncodesEveryOtherByte) {
  EXPECT_EQ(url_escape("AZaz09-._~"), "AZaz09-._~");
  EXPECT_EQ(url_escape("a b/c?d=e&f"), "a%20b%2Fc%3Fd%3De%26f");
  EXPECT_EQ(url_escape("m\xC2\xB3"), "m%C2%B3");  // UTF-8 bytes one by one
  EXPECT_EQ(url_escape(""), "");
}

}  // namespace
}  // namespace acdr
