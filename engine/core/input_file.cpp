// Whole-file reads with a type check and a size cap (see input_file.hpp).
#include "engine/core/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace acdr {
namespace {

const char* kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a file";
}

std::string too_large(std::size_t got, std::size_t max, const std::string& what) {
  return "file too large (got " + std::to_string(got) + " bytes, expected at most " + std::to_string(max) + " for " + what + ")";
}

/// Closes the descriptor on every way out.
struct Fd {
  int fd;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

}  // namespace

std::optional<std::string> read_input_file(const std::string& path, std::size_t max_bytes,
                                           const std::string& what, std::string* error) {
  auto fail = [&](std::string message) -> std::optional<std::string> {
    if (error) *error = std::move(message);
    return std::nullopt;
  };
  // The type first, so that not even open() touches a device; then again on the descriptor,
  // in case the name was swapped in between.
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0) {
    const int e = errno;
    return fail(std::string("cannot open the file: ") + std::strerror(e) + " (expected " + what + ")");
  }
  if (!S_ISREG(st.st_mode)) {
    return fail(std::string("not a regular file (got ") + kind_of(st.st_mode) + ", expected " + what + ")");
  }
  Fd file{::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC)};
  if (file.fd < 0) {
    const int e = errno;
    return fail(std::string("cannot open the file: ") + std::strerror(e) + " (expected " + what + ")");
  }
  if (::fstat(file.fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    return fail(std::string("not a regular file (got ") + kind_of(st.st_mode) + ", expected " + what + ")");
  }
  if (st.st_size < 0 || static_cast<std::size_t>(st.st_size) > max_bytes) {
    return fail(too_large(static_cast<std::size_t>(st.st_size), max_bytes, what));
  }
  // Read up to one byte past the cap: a file that grew past it since fstat is refused too.
  std::string bytes(static_cast<std::size_t>(st.st_size) + 1, '\0');
  std::size_t have = 0;
  for (;;) {
    if (have == bytes.size()) {
      if (bytes.size() > max_bytes) return fail(too_large(have, max_bytes, what));
      bytes.resize(std::min(max_bytes + 1, bytes.size() * 2 + 4096));
    }
    const ssize_t n = ::read(file.fd, bytes.data() + have, bytes.size() - have);
    if (n < 0) {
      if (errno == EINTR) continue;
      const int e = errno;
      return fail(std::string("cannot read the file: ") + std::strerror(e) + " (expected " + what + ")");
    }
    if (n == 0) break;
    have += static_cast<std::size_t>(n);
  }
  if (have > max_bytes) return fail(too_large(have, max_bytes, what));
  bytes.resize(have);
  return bytes;
}

}  // namespace acdr
