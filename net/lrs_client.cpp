// The LRS statements resource: see lrs_client.hpp.
#include "net/lrs_client.hpp"

#include <algorithm>
#include <cctype>
#include <nlohmann/json.hpp>

namespace acdr {

namespace {

constexpr std::size_t kMaxMessage = 600;

// The store's own words, on one line: a JSON body's "message" (and its warnings, as Learning
// Locker sends them), else the body's text, shortened.
std::string store_words(const std::string& body) {
  std::string words;
  try {
    const nlohmann::json json = nlohmann::json::parse(body);
    if (json.is_object() && json.contains("message") && json["message"].is_string()) {
      words = json["message"].get<std::string>();
      if (json.contains("warnings")) words += " " + json["warnings"].dump();
    } else {
      words = json.dump();
    }
  } catch (const nlohmann::json::exception&) {
    words = body;
  }
  for (char& c : words) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  }
  if (words.size() > kMaxMessage) words = words.substr(0, kMaxMessage) + "...";
  return words;
}

std::string status_line(long status, const std::string& body) {
  std::string line = "HTTP " + std::to_string(status);
  const std::string words = store_words(body);
  if (!words.empty()) line += ": " + words;
  return line;
}

}  // namespace

const char* lrs_answer_name(LrsAnswer answer) {
  switch (answer) {
    case LrsAnswer::kStored:
      return "stored";
    case LrsAnswer::kAlreadyStored:
      return "already stored";
    case LrsAnswer::kTryLater:
      return "try later";
    case LrsAnswer::kConfigProblem:
      return "configuration problem";
    case LrsAnswer::kRejected:
      return "rejected";
  }
  return "try later";
}

LrsReply classify_lrs_response(const HttpResponse& response, const std::string& url) {
  LrsReply reply;
  reply.status = response.status;
  if (!response.answered) {
    reply.answer = LrsAnswer::kTryLater;
    reply.message = "no answer from " + url + ": " + response.error;
    return reply;
  }
  const long s = response.status;
  if (s >= 200 && s < 300) {
    reply.answer = LrsAnswer::kStored;
    reply.message = "HTTP " + std::to_string(s);
  } else if (s == 409) {
    reply.answer = LrsAnswer::kAlreadyStored;
    reply.message =
        "the store already holds a statement with this id (" + status_line(s, response.body) + ")";
  } else if (s == 408 || s == 425 || s == 429 || s >= 500) {
    reply.answer = LrsAnswer::kTryLater;
    reply.message = url + " answered " + status_line(s, response.body);
  } else if (s == 401 || s == 403) {
    reply.answer = LrsAnswer::kConfigProblem;
    reply.message = url + " refused the credentials (" + status_line(s, response.body) +
                    "): check the LRS key and secret";
  } else if (s == 404 || s == 405 || (s >= 300 && s < 400) || s < 200) {
    reply.answer = LrsAnswer::kConfigProblem;
    std::string where = response.header("location");
    reply.message = url + " is not an xAPI statements resource (" + status_line(s, response.body) +
                    (where.empty() ? "" : ", to " + where) + "): check the LRS endpoint";
  } else {
    reply.answer = LrsAnswer::kRejected;
    reply.message = "the store refused the statement (" + status_line(s, response.body) + ")";
  }
  return reply;
}

LrsClient::LrsClient(LrsConfig config) : config_(std::move(config)) {}

std::string LrsClient::statements_url() const {
  return config_.endpoint + "statements";
}

LrsReply LrsClient::put_statement(const std::string& statement_id,
                                  const std::string& statement_json) {
  HttpRequest request;
  request.method = "PUT";
  request.url = statements_url() + "?statementId=" + url_escape(statement_id);
  request.headers = {{"Content-Type", "application/json"}, {"X-Experience-API-Version", "1.0.3"}};
  request.body = statement_json;
  request.user = config_.key;
  request.password = config_.secret;
  request.timeout_s = config_.timeout_s;
  request.connect_timeout_s = std::min(5.0, config_.timeout_s);
  return classify_lrs_response(http_.send(request), statements_url());
}

}  // namespace acdr
