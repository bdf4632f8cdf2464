// Reading a whole input file the user or an author named (a scenario, a mesh, a trajectory, a
// case file), safely: only a regular file is read (a FIFO would block forever, /dev/zero and
// /dev/urandom never end, a directory reads as nothing), it is opened without blocking, and
// its size is capped before reading and again while reading, in case it grows.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

namespace acdr {

/// Size caps of the files the program reads (bytes), documented in docs/scenario-format.md.
inline constexpr std::size_t kMaxScenarioFileBytes = std::size_t{4} << 20;      ///< 4 MiB
inline constexpr std::size_t kMaxMeshFileBytes = std::size_t{64} << 20;         ///< 64 MiB
inline constexpr std::size_t kMaxTrajectoryFileBytes = std::size_t{64} << 20;   ///< 64 MiB
inline constexpr std::size_t kMaxCaseFileBytes = std::size_t{4} << 20;          ///< 4 MiB
inline constexpr std::size_t kMaxWaypointFileBytes = std::size_t{4} << 20;      ///< 4 MiB
/// Cache files (distance grids, generated meshes): the largest grid the scenario budget allows
/// is far smaller.
inline constexpr std::size_t kMaxCacheFileBytes = std::size_t{1} << 30;         ///< 1 GiB

/// The bytes of `path`, or nullopt with `error` set to what is wrong, without the path (the
/// caller names the file in its own form): "not a regular file (got a FIFO, expected a mesh
/// file)", "file too large (got 70000000 bytes, expected at most 67108864)", "cannot open the
/// file: No such file or directory (expected a readable mesh file)". A symbolic link is
/// followed, and refused when it leads to anything but a regular file. `what` names the
/// expected file in messages ("a mesh file").
std::optional<std::string> read_input_file(const std::string& path, std::size_t max_bytes,
                                           const std::string& what, std::string* error);

}  // namespace acdr
