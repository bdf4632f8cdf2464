// On-disk cache files: XDG location, atomic write.
#include "engine/core/disk_cache.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/core/input_file.hpp"
#include "engine/core/state_hash.hpp"

namespace acdr {

std::string default_cache_dir(const std::string& sub) {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg && *xdg) return std::string(xdg) + "/acdr/" + sub;
  const char* home = std::getenv("HOME");
  if (home && *home) return std::string(home) + "/.cache/acdr/" + sub;
  return "";
}

std::string cache_file_path(const std::string& dir, std::uint64_t key, const std::string& suffix) {
  return dir + "/" + hash_hex(key) + suffix;
}

std::optional<std::string> read_cache_file(const std::string& path) {
  // A cache file is ours, but its directory is the user's: the same checks as any input.
  return read_input_file(path, kMaxCacheFileBytes, "a cache file", nullptr);
}

bool write_cache_file(const std::string& path, std::string_view bytes, std::string* error) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(fs::path(path).parent_path(), ec);
  if (ec) {
    if (error) *error = fs::path(path).parent_path().string() + ": cannot create the cache directory (" + ec.message() + ")";
    return false;
  }
  // A name unique to this process, renamed over the final one (atomic on POSIX).
  const std::string tmp = path + ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      fs::remove(tmp, ec);
      if (error) *error = tmp + ": cannot write the cache file (disk full or read-only?)";
      return false;
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    if (error) *error = path + ": cannot move the cache file into place (" + ec.message() + ")";
    return false;
  }
  return true;
}

}  // namespace acdr
