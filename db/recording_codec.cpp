// zlib compression of recordings: see recording_codec.hpp.
#include "db/recording_codec.hpp"

#include <zlib.h>

#include <string>

namespace acdr {

DbResult<std::vector<std::uint8_t>> compress_recording(std::span<const std::uint8_t> raw) {
  uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
  std::vector<std::uint8_t> packed(packed_size);
  const int rc = compress2(packed.data(), &packed_size, raw.data(),
                           static_cast<uLong>(raw.size()), 6);
  if (rc != Z_OK) {
    return DbError{"recording compression failed (zlib error " + std::to_string(rc) + ", " +
                       std::to_string(raw.size()) + " bytes)",
                   0};
  }
  packed.resize(packed_size);
  return packed;
}

DbResult<std::vector<std::uint8_t>> decompress_recording(std::span<const std::uint8_t> packed,
                                                         std::uint64_t raw_size) {
  std::vector<std::uint8_t> raw(static_cast<std::size_t>(raw_size));
  uLongf out_size = static_cast<uLongf>(raw_size);
  uLong in_size = static_cast<uLong>(packed.size());
  // uncompress2 also reports how much input it used, so trailing garbage is detected.
  const int rc = uncompress2(raw.data(), &out_size, packed.data(), &in_size);
  if (rc != Z_OK || out_size != raw_size || in_size != packed.size()) {
    return DbError{"recording is corrupt: zlib gave " + std::to_string(rc) + " after " +
                       std::to_string(out_size) + " of " + std::to_string(raw_size) +
                       " expected bytes",
                   0};
  }
  return raw;
}

}  // namespace acdr
