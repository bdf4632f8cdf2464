// Test learning record stores as child processes on 127.0.0.1, for the tests of sending xAPI
// statements: the validating test endpoint (tests/lrs/test_lrs.js, which checks every statement
// with Learning Locker's xapi-validation and keeps what it stored in a file, so it can be
// killed and restarted) and Learning Locker's own statements service (xapi-statements, in
// memory). Both need node and `npm ci` in tests/lrs (scripts/test does it).
#pragma once

#include <sys/types.h>

#include <map>
#include <string>
#include <vector>

namespace acdr::test_support {

/// "" when node and the test LRS packages are there, else what is missing (for GTEST_SKIP).
std::string test_lrs_missing(const std::string& source_dir);

struct TestLrsOptions {
  std::string source_dir;  ///< the repository (tests/lrs lives there)
  std::string store;       ///< the file that keeps stored statements (and store + ".log")
  std::string key = "acdr-station";
  std::string secret = "s3cret";
  int port = 0;        ///< 0: a free port
  int exit_after = 0;  ///< > 0: drop the connection and exit after storing this many (this run)
};

/// A running store. Stopped (SIGTERM, then SIGKILL) when destroyed.
class LrsProcess {
 public:
  /// tests/lrs/test_lrs.js with `options`; waits until it listens. On failure `error` is set
  /// and the process is not running.
  static LrsProcess start_test_lrs(const TestLrsOptions& options, std::string* error);
  /// Learning Locker's statements service (xapi-statements) on a free port, statements in
  /// memory, its test authenticator (any key). Waits until it listens.
  static LrsProcess start_learning_locker(const std::string& source_dir, std::string* error);

  LrsProcess() = default;
  LrsProcess(LrsProcess&& other) noexcept;
  LrsProcess& operator=(LrsProcess&& other) noexcept;
  ~LrsProcess();

  bool running() const { return pid_ > 0; }
  int port() const { return port_; }
  /// The xAPI endpoint, e.g. http://127.0.0.1:PORT/xapi/
  std::string endpoint() const;
  /// Waits up to `timeout_s` for the process to exit by itself (--exit-after); true if it did.
  bool wait_exit(double timeout_s);
  /// Stops it now (SIGKILL) and reaps it.
  void kill_now();

 private:
  pid_t pid_ = -1;
  int port_ = 0;
  std::string base_path_;  // "/xapi/" or "/xAPI/"
};

/// The ids in a test_lrs.js store file, in the order stored (each stored once by design).
std::vector<std::string> stored_ids(const std::string& store);
/// How many requests of each outcome the test store logged for each id: [id][outcome].
std::map<std::string, std::map<std::string, int>> logged_outcomes(const std::string& store);

}  // namespace acdr::test_support
