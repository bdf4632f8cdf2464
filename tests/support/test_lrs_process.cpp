// Test learning record stores as child processes: see test_lrs_process.hpp.
#include "tests/support/test_lrs_process.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

namespace acdr::test_support {

namespace {

using Clock = std::chrono::steady_clock;

std::string lrs_dir(const std::string& source_dir) {
  return source_dir + "/tests/lrs";
}

bool node_on_path() {
  return std::system("command -v node >/dev/null 2>&1") == 0;
}

// A port nobody listens on right now (bound and released; the child binds it next).
int free_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = 0;
  socklen_t len = sizeof addr;
  int port = 0;
  if (bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0 &&
      getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) == 0) {
    port = ntohs(addr.sin_port);
  }
  close(fd);
  return port;
}

// Starts `argv` with `env` added, stdout to the file `out` and stderr to `err` (files, not
// pipes: a server that logs every request must not die of a closed pipe).
pid_t spawn(const std::vector<std::string>& argv, const std::vector<std::string>& env,
            const std::string& out, const std::string& err) {
  // A restarted store writes to the same file: the old "listening" line must be gone before
  // anyone looks for the new one.
  std::remove(out.c_str());
  const pid_t pid = fork();
  if (pid == 0) {
    const int out_fd = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    const int err_fd = open(err.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0600);
    if (out_fd >= 0) dup2(out_fd, STDOUT_FILENO);
    if (err_fd >= 0) dup2(err_fd, STDERR_FILENO);
    for (const std::string& e : env) putenv(const_cast<char*>(e.c_str()));
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execvp(args[0], args.data());
    _exit(127);
  }
  return pid;
}

std::string read_file(const std::string& path);

// Waits until the file `out` has a line containing `marker` (returned), the process `pid` has
// ended, or `timeout_s` has passed ("" in both cases).
std::string wait_for_line(pid_t pid, const std::string& out, const std::string& marker,
                          double timeout_s) {
  const Clock::time_point end = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                   std::chrono::duration<double>(timeout_s));
  while (Clock::now() < end) {
    const std::string text = read_file(out);
    const std::size_t at = text.find(marker);
    if (at != std::string::npos) {
      const std::size_t eol = text.find('\n', at);
      if (eol != std::string::npos) return text.substr(at, eol - at);
    }
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) return "";
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return "";
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

std::string test_lrs_missing(const std::string& source_dir) {
  if (!node_on_path()) return "node is not installed (the test LRS runs on node)";
  const std::string dir = lrs_dir(source_dir) + "/node_modules";
  for (const char* package : {"@learninglocker/xapi-validation", "xapi-statements"}) {
    if (!std::filesystem::exists(dir + "/" + package + "/package.json")) {
      return dir + "/" + package +
             " is missing: run scripts/test (or npm ci in tests/lrs) to install the test LRS";
    }
  }
  return "";
}

LrsProcess LrsProcess::start_test_lrs(const TestLrsOptions& options, std::string* error) {
  std::vector<std::string> argv = {"node",    lrs_dir(options.source_dir) + "/test_lrs.js",
                                   "--store", options.store,
                                   "--port",  std::to_string(options.port)};
  if (!options.key.empty()) {
    argv.insert(argv.end(), {"--key", options.key, "--secret", options.secret});
  }
  if (options.exit_after > 0) {
    argv.insert(argv.end(), {"--exit-after", std::to_string(options.exit_after)});
  }
  LrsProcess p;
  p.pid_ = spawn(argv, {}, options.store + ".stdout", options.store + ".stderr");
  p.base_path_ = "/xapi/";
  if (p.pid_ <= 0) {
    *error = "cannot start node";
    return LrsProcess();
  }
  const std::string line = wait_for_line(p.pid_, options.store + ".stdout", "listening on ", 60.0);
  if (line.empty()) {
    p.kill_now();
    *error = "the test LRS did not start: " + read_file(options.store + ".stderr");
    return LrsProcess();
  }
  p.port_ = std::atoi(line.substr(std::string("listening on ").size()).c_str());
  return p;
}

LrsProcess LrsProcess::start_learning_locker(const std::string& source_dir, std::string* error) {
  LrsProcess p;
  p.port_ = free_port();
  p.base_path_ = "/xAPI/";
  const std::string work = std::filesystem::temp_directory_path().string() + "/acdr-ll-" +
                           std::to_string(getpid()) + "-" + std::to_string(p.port_);
  std::filesystem::create_directories(work);
  const std::string server = lrs_dir(source_dir) + "/node_modules/xapi-statements/dist/server.js";
  p.pid_ = spawn(
      {"node", server},
      {"EXPRESS_PORT=" + std::to_string(p.port_), "AUTH_REPO=test", "EVENTS_REPO=test",
       "MODELS_REPO=memory", "STORAGE_REPO=local", "FS_LOCAL_STORAGE_DIR=" + work + "/storage",
       "EXPRESS_MORGAN_DIRECTORY=" + work + "/logs", "WINSTON_CONSOLE_LEVEL=info"},
      work + "/stdout.log", work + "/stderr.log");
  if (p.pid_ <= 0) {
    *error = "cannot start node";
    return LrsProcess();
  }
  const std::string line = wait_for_line(p.pid_, work + "/stdout.log", "Listening on port", 90.0);
  if (line.empty()) {
    p.kill_now();
    *error =
        "Learning Locker's statements service did not start: " + read_file(work + "/stderr.log");
    return LrsProcess();
  }
  return p;
}

LrsProcess::LrsProcess(LrsProcess&& other) noexcept
    : pid_(other.pid_), port_(other.port_), base_path_(std::move(other.base_path_)) {
  other.pid_ = -1;
}

LrsProcess& LrsProcess::operator=(LrsProcess&& other) noexcept {
  if (this != &other) {
    kill_now();
    pid_ = other.pid_;
    port_ = other.port_;
    base_path_ = std::move(other.base_path_);
    other.pid_ = -1;
  }
  return *this;
}

LrsProcess::~LrsProcess() {
  kill_now();
}

std::string LrsProcess::endpoint() const {
  return "http://127.0.0.1:" + std::to_string(port_) + base_path_;
}

bool LrsProcess::wait_exit(double timeout_s) {
  if (pid_ <= 0) return true;
  const Clock::time_point end = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                   std::chrono::duration<double>(timeout_s));
  while (Clock::now() < end) {
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

void LrsProcess::kill_now() {
  if (pid_ <= 0) return;
  kill(pid_, SIGKILL);
  int status = 0;
  waitpid(pid_, &status, 0);
  pid_ = -1;
}

std::vector<std::string> stored_ids(const std::string& store) {
  std::vector<std::string> ids;
  std::ifstream in(store);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty()) ids.push_back(nlohmann::json::parse(line)["id"].get<std::string>());
  }
  return ids;
}

std::map<std::string, std::map<std::string, int>> logged_outcomes(const std::string& store) {
  std::map<std::string, std::map<std::string, int>> out;
  std::ifstream in(store + ".log");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const nlohmann::json entry = nlohmann::json::parse(line);
    ++out[entry["id"].get<std::string>()][entry["outcome"].get<std::string>()];
  }
  return out;
}

}  // namespace acdr::test_support
