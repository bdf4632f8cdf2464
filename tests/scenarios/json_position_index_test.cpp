// The pointer -> line index: keys, array items, escapes, duplicates, depth bound.
#include "scenarios/json_position_index.hpp"

#include <gtest/gtest.h>

namespace acdr {
namespace {

TEST(JsonPositionIndex, FindsKeysAndItemsByLine) {
  const std::string text =
      "{\n"
      "  \"a\": 1,\n"
      "  \"b\": {\n"
      "    \"c\": [10,\n"
      "           {\"d\": true}]\n"
      "  }\n"
      "}\n";
  const JsonPositionIndex index(text);
  EXPECT_EQ(index.find("").line, 1);
  EXPECT_EQ(index.find("/a").line, 2);
  EXPECT_EQ(index.find("/a").column, 3);
  EXPECT_EQ(index.find("/b").line, 3);
  EXPECT_EQ(index.find("/b/c").line, 4);
  EXPECT_EQ(index.find("/b/c/0").line, 4);
  EXPECT_EQ(index.find("/b/c/1").line, 5);
  EXPECT_EQ(index.find("/b/c/1/d").line, 5);
  // A missing key falls back to its nearest recorded ancestor.
  EXPECT_EQ(index.find("/b/missing").line, 3);
  EXPECT_EQ(index.find("/nothing/at/all").line, 1);
}

TEST(JsonPositionIndex, DecodesEscapedKeysAndEscapesPointers) {
  const std::string text = "{\n\"a/b\": 1,\n\"t~\": 2,\n\"\\u0078\": 3}";
  const JsonPositionIndex index(text);
  EXPECT_EQ(index.find("/a~1b").line, 2);
  EXPECT_EQ(index.find("/t~0").line, 3);
  EXPECT_EQ(index.find("/x").line, 4);
  EXPECT_EQ(escape_pointer_token("a/b~c"), "a~1b~0c");
}

TEST(JsonPositionIndex, ReportsDuplicateKeys) {
  std::vector<DuplicateKey> dups;
  const JsonPositionIndex index("{\"k\": 1,\n \"o\": {\"z\": 0},\n \"k\": 2}", &dups);
  ASSERT_EQ(dups.size(), 1u);
  EXPECT_EQ(dups[0].json_path, "/k");
  EXPECT_EQ(dups[0].first.line, 1);
  EXPECT_EQ(dups[0].second.line, 3);
}

TEST(JsonPositionIndex, DeepNestingIsBoundedAndSafe) {
  const std::string text = std::string(200000, '[') + std::string(200000, ']');
  const JsonPositionIndex index(text);
  EXPECT_EQ(index.find("/0/0/0").line, 1);
}

TEST(JsonPositionIndex, MalformedTextNeverReadsPastTheEnd) {
  for (const char* t : {"{", "{\"a", "{\"a\":", "[1,", "\"\\", "{\"a\" 1}", "}}}", "{:::}"}) {
    const JsonPositionIndex index(t);
    EXPECT_GE(index.find("/a").line, 1) << t;
  }
}

TEST(JsonPositionIndex, OffsetToLineAndColumn) {
  const JsonPositionIndex index("ab\ncd\n");
  EXPECT_EQ(index.position_of_offset(0).line, 1);
  EXPECT_EQ(index.position_of_offset(4).line, 2);
  EXPECT_EQ(index.position_of_offset(4).column, 2);
}

}  // namespace
}  // namespace acdr

namespace acdr {
namespace {

// Found by the loader fuzz test: a '}' inside an array used to stall the scan.
TEST(JsonPositionIndex, MismatchedClosersMakeProgress) {
  for (const char* t : {"[}", "[1 } 2]", "{\"a\": [}]}", "[:]", "{\"a\": :}"}) {
    const JsonPositionIndex index(t);
    EXPECT_GE(index.find("").line, 1) << t;
  }
}

}  // namespace
}  // namespace acdr
