// FNV-1a 64 against the published test vectors (Fowler/Noll/Vo reference test suite).
#include "scenarios/content_hash.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

TEST(ContentHash, MatchesReferenceVectors) {
  EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ull);
  EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(fnv1a64("foobar"), 0x85944171f73967e8ull);
}

TEST(ContentHash, HexIsSixteenLowerCaseDigits) {
  EXPECT_EQ(fnv1a64_hex(""), "cbf29ce484222325");
  EXPECT_EQ(fnv1a64_hex("foobar"), "85944171f73967e8");
}

TEST(ContentHash, OneByteChangesTheHash) {
  EXPECT_NE(fnv1a64_hex("{\"a\": 1}"), fnv1a64_hex("{\"a\": 2}"));
}

}  // namespace
}  // namespace acdr
