// Process identity and liveness from /proc (Linux): see writer_identity.hpp.
#include "db/writer_identity.hpp"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace acdr {

namespace {

struct ProcStat {
  bool exists = false;
  char state = '?';
  std::int64_t start_ticks = 0;
};

// /proc/<pid>/stat: "pid (comm) state ppid ... starttime(22) ...". comm may contain spaces and
// parentheses, so parse from the last ')'.
ProcStat read_proc_stat(std::int64_t pid) {
  ProcStat out;
  std::ifstream file("/proc/" + std::to_string(pid) + "/stat");
  if (!file) return out;
  std::string line;
  std::getline(file, line);
  const std::size_t close = line.rfind(')');
  if (close == std::string::npos) return out;
  out.exists = true;
  std::istringstream rest(line.substr(close + 1));
  std::string field;
  // Fields after comm start at 3 (state); starttime is field 22.
  for (int index = 3; index <= 22 && (rest >> field); ++index) {
    if (index == 3) out.state = field.empty() ? '?' : field[0];
    if (index == 22) out.start_ticks = std::strtoll(field.c_str(), nullptr, 10);
  }
  return out;
}

std::string read_first_line(const char* path) {
  std::ifstream file(path);
  std::string line;
  if (file) std::getline(file, line);
  return line;
}

std::string host_identity() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) name[0] = '\0';
  std::string boot = read_first_line("/proc/sys/kernel/random/boot_id");
  return std::string(name) + "/" + (boot.empty() ? "unknown-boot" : boot);
}

}  // namespace

WriterIdentity current_writer() {
  WriterIdentity self;
  self.pid = static_cast<std::int64_t>(getpid());
  self.start_ticks = read_proc_stat(self.pid).start_ticks;
  self.host = host_identity();
  return self;
}

WriterState writer_state(const WriterIdentity& writer) {
  if (writer.pid <= 0 || writer.host != host_identity()) return WriterState::kGone;
  const ProcStat stat = read_proc_stat(writer.pid);
  if (!stat.exists) {
    // No /proc entry: either no such process or no /proc at all; ask the kernel directly.
    // EPERM means the process exists but belongs to someone else.
    if (kill(static_cast<pid_t>(writer.pid), 0) == 0 || errno == EPERM) return WriterState::kAlive;
    return WriterState::kGone;
  }
  // A zombie has exited and only waits for its parent to reap it; 'X' is dead.
  if (stat.state == 'Z' || stat.state == 'X') return WriterState::kGone;
  if (writer.start_ticks != 0 && stat.start_ticks != writer.start_ticks) return WriterState::kGone;
  return WriterState::kAlive;
}

}  // namespace acdr
