// A small HTTP client over libcurl: one request at a time, the connection kept open between
// requests to the same server. One HttpClient per thread. Redirects are not followed (a
// statement PUT answered by a redirect is a configuration problem to report, not to chase).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace acdr {

struct HttpRequest {
  std::string method = "GET";  ///< GET, PUT or POST
  std::string url;
  std::vector<std::pair<std::string, std::string>> headers;  ///< name, value
  std::string body;
  /// HTTP Basic authentication when `user` is not empty.
  std::string user;
  std::string password;
  double connect_timeout_s = 5.0;  ///< to open the connection
  double timeout_s = 30.0;         ///< for the whole exchange
};

struct HttpResponse {
  /// false: no complete answer arrived (refused, reset, timed out, name not resolved, ...);
  /// `error` says what, and `status` is 0.
  bool answered = false;
  std::string error;
  long status = 0;
  std::string body;
  /// Response headers, names in lower case, as received.
  std::vector<std::pair<std::string, std::string>> headers;

  /// The first header of that (lower-case) name, or "".
  std::string header(const std::string& lower_name) const;
};

/// `text` percent-encoded for a URL's query or path (RFC 3986: letters, digits and "-._~" pass,
/// every other byte is %XX), by libcurl.
std::string url_escape(const std::string& text);

class HttpClient {
 public:
  HttpClient();
  ~HttpClient();
  HttpClient(const HttpClient&) = delete;
  HttpClient& operator=(const HttpClient&) = delete;

  /// Sends `request` and waits for the answer (or the timeout). Never throws for network
  /// trouble: that is an unanswered response.
  HttpResponse send(const HttpRequest& request);

 private:
  void* curl_ = nullptr;  // CURL*, reused so the connection stays open
};

}  // namespace acdr
