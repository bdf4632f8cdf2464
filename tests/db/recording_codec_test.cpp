// Tests of db/recording_codec.cpp: lossless round trip, and corrupt data is an error.
#include "db/recording_codec.hpp"

#include <gtest/gtest.h>

#include <random>

namespace acdr {
namespace {

TEST(RecordingCodec, RoundTripIsLossless) {
  std::mt19937 rng(42);
  for (std::size_t size : {std::size_t{0}, std::size_t{1}, std::size_t{1000}, std::size_t{300000}}) {
    std::vector<std::uint8_t> raw(size);
    for (auto& b : raw) b = static_cast<std::uint8_t>(rng() % 7);  // compressible
    DbResult<std::vector<std::uint8_t>> packed = compress_recording(raw);
    ASSERT_TRUE(packed.ok());
    if (size >= 1000) {
      EXPECT_LT(packed->size(), size / 2);
    }
    DbResult<std::vector<std::uint8_t>> back = decompress_recording(packed.value(), size);
    ASSERT_TRUE(back.ok()) << back.error().message;
    EXPECT_EQ(back.value(), raw);
  }
}

TEST(RecordingCodec, CorruptOrMisSizedDataIsAnError) {
  std::vector<std::uint8_t> raw(5000, 3);
  std::vector<std::uint8_t> packed = compress_recording(raw).value();
  EXPECT_FALSE(decompress_recording(packed, 4999).ok());
  EXPECT_FALSE(decompress_recording(packed, 5001).ok());
  std::vector<std::uint8_t> truncated(packed.begin(), packed.end() - 3);
  EXPECT_FALSE(decompress_recording(truncated, 5000).ok());
  std::vector<std::uint8_t> flipped = packed;
  flipped[flipped.size() / 2] ^= 0x55;
  EXPECT_FALSE(decompress_recording(flipped, 5000).ok());
  std::vector<std::uint8_t> trailing = packed;
  trailing.push_back(0);
  EXPECT_FALSE(decompress_recording(trailing, 5000).ok());
}

}  // namespace
}  // namespace acdr
