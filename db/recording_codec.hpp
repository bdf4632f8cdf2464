// Compression of attempt recordings (the input and frame stream) with zlib: a 1 kHz frame
// stream is large and very regular, and is stored once and read rarely (replay, re-score).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "db/db_result.hpp"

namespace acdr {

/// zlib (RFC 1950) stream of `raw` at compression level 6 (zlib's default balance).
DbResult<std::vector<std::uint8_t>> compress_recording(std::span<const std::uint8_t> raw);

/// Inflates a zlib stream that must decode to exactly `raw_size` bytes (stored with it); a
/// corrupt or truncated stream is an error, never a short recording.
DbResult<std::vector<std::uint8_t>> decompress_recording(std::span<const std::uint8_t> packed,
                                                         std::uint64_t raw_size);

}  // namespace acdr
