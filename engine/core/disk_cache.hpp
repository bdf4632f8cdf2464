// A small on-disk cache for derived data that is slow to build and cheap to load (signed
// distance grids, generated bone meshes): one file per content key, written atomically so a
// crash or a concurrent writer never leaves a half file under the final name.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace acdr {

/// $XDG_CACHE_HOME/acdr/<sub>, else $HOME/.cache/acdr/<sub>; empty when neither is set.
std::string default_cache_dir(const std::string& sub);

/// "<dir>/<16 hex digits of key><suffix>".
std::string cache_file_path(const std::string& dir, std::uint64_t key, const std::string& suffix);

/// The whole file, or nullopt when it does not exist, cannot be read, is not a regular file or
/// is larger than kMaxCacheFileBytes (engine/core/input_file.hpp).
std::optional<std::string> read_cache_file(const std::string& path);

/// Creates the directory if needed, writes to a temporary name and renames it into place.
bool write_cache_file(const std::string& path, std::string_view bytes, std::string* error);

}  // namespace acdr
