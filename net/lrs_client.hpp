// The xAPI 1.0.3 statements resource of a learning record store, as a client that stores one
// statement at a time under its own id: PUT {endpoint}statements?statementId=ID with the
// statement as JSON, HTTP Basic authentication and X-Experience-API-Version: 1.0.3. PUT with
// the id makes a repeated send harmless: the store answers 204 again, or 409 Conflict when it
// holds a statement of that id already (xAPI 1.0.3, Communication 2.1.2), which for us means
// delivered too.
//
// Each answer is sorted by what the sender should do with the statement:
//   2xx                    stored                 mark it sent
//   409                    already stored         mark it sent
//   408, 425, 429, 5xx,    try again later        keep it queued, back off
//   no answer at all
//   401, 403               sign-in refused        keep it, stop sending: the configuration is wrong
//   404, 405, 3xx          no statements resource keep it, stop sending: the endpoint is wrong
//   other 4xx (400, 413)   refused for good       mark it failed with the store's message
#pragma once

#include <string>

#include "net/http_client.hpp"
#include "net/lrs_config.hpp"

namespace acdr {

enum class LrsAnswer {
  kStored,         ///< the store took it now
  kAlreadyStored,  ///< the store had it (409): delivered before
  kTryLater,       ///< the store or the network is not available now
  kConfigProblem,  ///< credentials or endpoint wrong: no statement can go until fixed
  kRejected,       ///< this statement will never be accepted as it is
};

/// "stored", "already stored", "try later", "configuration problem", "rejected".
const char* lrs_answer_name(LrsAnswer answer);

struct LrsReply {
  LrsAnswer answer = LrsAnswer::kTryLater;
  long status = 0;      ///< the HTTP status, 0 when there was no answer
  std::string message;  ///< one line for people: what happened, with the store's own words
};

/// Sorts an HTTP exchange as in the table above (`url` for messages).
LrsReply classify_lrs_response(const HttpResponse& response, const std::string& url);

class LrsClient {
 public:
  explicit LrsClient(LrsConfig config);

  /// Stores `statement_json` (a statement object whose "id" is `statement_id`).
  LrsReply put_statement(const std::string& statement_id, const std::string& statement_json);

  /// {endpoint}statements
  std::string statements_url() const;
  const LrsConfig& config() const { return config_; }

 private:
  LrsConfig config_;
  HttpClient http_;
};

}  // namespace acdr
