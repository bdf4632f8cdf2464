// Runs the acdr program as a child process for end-to-end tests: with an optional address-space
// limit (setrlimit RLIMIT_AS, as `ulimit -v` sets it), a wall-clock limit after which it is
// killed, and its output and how it ended captured.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace acdr::test {

struct ProcessResult {
  int exit_code = -1;   ///< the exit status when it exited, else -1
  int signal = 0;       ///< the signal that ended it, 0 when it exited
  bool timed_out = false;
  double seconds = 0.0;
  std::string output;   ///< stdout and stderr together
};

/// Runs `argv` (argv[0] a path) with `address_space_bytes` of address space (0: unlimited),
/// killing it after `timeout_s`.
inline ProcessResult run_process(const std::vector<std::string>& argv, std::size_t address_space_bytes,
                                 double timeout_s) {
  ProcessResult r;
  char tmpl[] = "/tmp/acdr_process_XXXXXX";
  const int out_fd = ::mkstemp(tmpl);
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(out_fd, 1);
    ::dup2(out_fd, 2);
    const int null_in = ::open("/dev/null", O_RDONLY);
    ::dup2(null_in, 0);
    if (address_space_bytes > 0) {
      struct rlimit lim{address_space_bytes, address_space_bytes};
      ::setrlimit(RLIMIT_AS, &lim);
    }
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (elapsed > timeout_s) {
      r.timed_out = true;
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  ::close(out_fd);
  std::ifstream in(tmpl, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  r.output = text.str();
  std::remove(tmpl);
  return r;
}

/// The 4 GB address-space limit a run must live within (`ulimit -v 4000000`, in KiB).
inline constexpr std::size_t kFourGigabytes = std::size_t{4000000} * 1024;

}  // namespace acdr::test
