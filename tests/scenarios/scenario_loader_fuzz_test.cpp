// Robustness of the loader: thousands of seeded random mutations of the box module (truncations,
// byte flips, deleted keys, renamed keys, numbers turned into strings, emptied arrays, values
// of the wrong kind, random bytes) must each return, never crash or hang, with well-formed
// errors; the mutations that can never be valid must be rejected at the mutated JSON path.
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "scenarios/object_reader.hpp"
#include "scenarios/scenario_loader.hpp"
#include "tests/scenarios/scenario_test_support.hpp"

namespace acdr {
namespace {

using nlohmann::json;

struct Site {
  std::string pointer;
  const json* value;
  bool is_member;  ///< an object member (its key can be renamed or deleted)
};

void collect(const json& v, const std::string& pointer, bool member, std::vector<Site>& out) {
  out.push_back({pointer, &v, member});
  if (v.is_object()) {
    for (auto it = v.begin(); it != v.end(); ++it) {
      collect(it.value(), pointer + "/" + it.key(), true, out);
    }
  } else if (v.is_array()) {
    for (std::size_t i = 0; i < v.size(); ++i) collect(v[i], pointer + "/" + std::to_string(i), false, out);
  }
}

int count_lines(const std::string& s) {
  int n = 1;
  for (char c : s) n += c == '\n' ? 1 : 0;
  return n;
}

/// Loads `text` and checks the invariants every result must satisfy.
LoadResult load_checked(const std::string& text) {
  LoadResult r;
  EXPECT_NO_THROW(r = load_scenario_text(text, "fuzz.json"));
  EXPECT_NE(r.ok(), !r.errors.empty());
  EXPECT_LE(r.errors.size(), LoadContext::kMaxErrors + 1);
  const int lines = count_lines(text);
  for (const ScenarioError& e : r.errors) {
    EXPECT_EQ(e.file, "fuzz.json");
    EXPECT_GE(e.line, 1);
    EXPECT_LE(e.line, lines);
    EXPECT_FALSE(e.message.empty());
    EXPECT_TRUE(e.json_path.empty() || e.json_path[0] == '/') << e.json_path;
    EXPECT_EQ(e.to_string().rfind("fuzz.json:", 0), 0u);
  }
  return r;
}

bool has_error_at(const LoadResult& r, const std::string& pointer) {
  for (const ScenarioError& e : r.errors) {
    if (e.json_path == pointer) return true;
  }
  return false;
}

class ScenarioLoaderFuzz : public ::testing::Test {
 protected:
  void SetUp() override {
    text_ = test::box_module_text();
    doc_ = json::parse(text_);
    collect(doc_, "", false, sites_);
    ASSERT_TRUE(load_scenario_text(text_, "fuzz.json").ok());
  }
  const Site& pick(std::mt19937_64& rng, bool (*accept)(const Site&)) {
    std::vector<const Site*> fits;
    for (const Site& s : sites_) {
      if (accept(s)) fits.push_back(&s);
    }
    return *fits[std::uniform_int_distribution<std::size_t>(0, fits.size() - 1)(rng)];
  }
  /// The document with the value at `pointer` replaced by `with`, pretty-printed.
  std::string with_value(const std::string& pointer, const json& with) const {
    json d = doc_;
    d[json::json_pointer(pointer)] = with;
    return d.dump(2);
  }

  std::string text_;
  json doc_;
  std::vector<Site> sites_;
};

TEST_F(ScenarioLoaderFuzz, TruncationsAlwaysFailWithOneError) {
  std::mt19937_64 rng(1);
  const std::size_t last = text_.find_last_not_of(" \n\r\t");
  for (int i = 0; i < 400; ++i) {
    const std::size_t cut = std::uniform_int_distribution<std::size_t>(0, last)(rng);
    const LoadResult r = load_checked(text_.substr(0, cut));
    ASSERT_FALSE(r.ok()) << "cut at " << cut;
    EXPECT_EQ(r.errors.size(), 1u);
  }
}

TEST_F(ScenarioLoaderFuzz, ByteFlipsNeverCrash) {
  std::mt19937_64 rng(2);
  for (int i = 0; i < 600; ++i) {
    std::string t = text_;
    const int flips = std::uniform_int_distribution<int>(1, 4)(rng);
    for (int f = 0; f < flips; ++f) {
      const std::size_t at = std::uniform_int_distribution<std::size_t>(0, t.size() - 1)(rng);
      t[at] = static_cast<char>(std::uniform_int_distribution<int>(0, 255)(rng));
    }
    load_checked(t);
  }
}

TEST_F(ScenarioLoaderFuzz, DeletedKeysNeverCrash) {
  std::mt19937_64 rng(3);
  int rejected = 0;
  for (int i = 0; i < 300; ++i) {
    const Site& s = pick(rng, [](const Site& x) { return x.is_member; });
    json d = doc_;
    const json::json_pointer p(s.pointer);
    d[p.parent_pointer()].erase(p.back());
    rejected += load_checked(d.dump(2)).ok() ? 0 : 1;
  }
  EXPECT_GT(rejected, 0);  // required keys exist, and the draw hits some
}

TEST_F(ScenarioLoaderFuzz, RenamedKeysAreAlwaysRejectedAtTheirPath) {
  std::mt19937_64 rng(4);
  for (int i = 0; i < 300; ++i) {
    const Site& s = pick(rng, [](const Site& x) { return x.is_member; });
    json d = doc_;
    const json::json_pointer p(s.pointer);
    const std::string renamed = p.back() + "_" + static_cast<char>('a' + rng() % 26);
    d[p.parent_pointer()][renamed] = d[p];
    d[p.parent_pointer()].erase(p.back());
    const std::string new_pointer = p.parent_pointer().to_string() + "/" + renamed;
    const LoadResult r = load_checked(d.dump(2));
    ASSERT_FALSE(r.ok()) << new_pointer;
    EXPECT_TRUE(has_error_at(r, new_pointer)) << new_pointer << "\n" << to_string(r.errors);
  }
}

TEST_F(ScenarioLoaderFuzz, NumbersTurnedIntoStringsAreAlwaysRejectedAtTheirPath) {
  std::mt19937_64 rng(5);
  for (int i = 0; i < 300; ++i) {
    const Site& s = pick(rng, [](const Site& x) { return x.value->is_number(); });
    const LoadResult r = load_checked(with_value(s.pointer, s.value->dump()));
    ASSERT_FALSE(r.ok()) << s.pointer;
    EXPECT_TRUE(has_error_at(r, s.pointer)) << s.pointer << "\n" << to_string(r.errors);
  }
}

TEST_F(ScenarioLoaderFuzz, EmptiedArraysAreAlwaysRejectedAtTheirPath) {
  std::mt19937_64 rng(6);
  for (int i = 0; i < 200; ++i) {
    const Site& s = pick(rng, [](const Site& x) { return x.value->is_array(); });
    const LoadResult r = load_checked(with_value(s.pointer, json::array()));
    ASSERT_FALSE(r.ok()) << s.pointer;
    EXPECT_TRUE(has_error_at(r, s.pointer)) << s.pointer << "\n" << to_string(r.errors);
  }
}

TEST_F(ScenarioLoaderFuzz, ValuesOfAnyKindNeverCrash) {
  std::mt19937_64 rng(7);
  const std::vector<json> replacements = {
      nullptr, true, false, 0, -1, 1e308, -1e308, 1e-300, 4294967296.0, -2147483649LL,
      18446744073709551615ULL, "", "x", std::string(5000, 'y'), json::array(), json::object(),
      json::array({1, 2, 3, 4, 5}), json::object({{"a", 1}}), "\xc3\xa9\xe2\x82\xac"};
  for (int i = 0; i < 600; ++i) {
    const Site& s = pick(rng, [](const Site&) { return true; });
    const json& with = replacements[rng() % replacements.size()];
    if (s.pointer.empty()) {
      load_checked(with.dump());
    } else {
      load_checked(with_value(s.pointer, with));
    }
  }
}

TEST_F(ScenarioLoaderFuzz, RandomBytesAndPathologicalInputsFail) {
  std::mt19937_64 rng(8);
  for (int i = 0; i < 300; ++i) {
    std::string t(std::uniform_int_distribution<std::size_t>(0, 300)(rng), '\0');
    for (char& c : t) c = static_cast<char>(rng() & 0xff);
    EXPECT_FALSE(load_checked(t).ok());
  }
  const std::vector<std::string> nasty = {
      "", " ", "\n\n\n", "null", "0", "\"\"", "{}", "[]",
      std::string(100000, '[') + std::string(100000, ']'),
      std::string(100000, '['),
      "{" + std::string(50000, ' ') + "\"a\":" + std::string(200000, '[') + std::string(200000, ']') + "}",
      "{\"a\": 1e999}", "{\"a\": -1e999}", "{\"a\": \"\xff\xfe\"}", std::string("{\"a\":\0}", 7),
      "{\"format_version\": 1, \"format_version\": 1}", "\xEF\xBB\xBF", "{\"\\ud800\": 1}",
  };
  for (const std::string& t : nasty) EXPECT_FALSE(load_checked(t).ok());
}

TEST_F(ScenarioLoaderFuzz, ManyUnknownKeysAreCappedNotFlooded) {
  json d = doc_;
  for (int i = 0; i < 5000; ++i) d["unknown_" + std::to_string(i)] = i;
  const LoadResult r = load_checked(d.dump());
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.errors.size(), LoadContext::kMaxErrors + 1);
  EXPECT_NE(r.errors.back().message.find("too many errors"), std::string::npos);
}

TEST_F(ScenarioLoaderFuzz, OversizedFileIsRefused) {
  const std::string big = "{\"pad\": \"" + std::string(kMaxScenarioFileBytes, 'p') + "\"}";
  const LoadResult r = load_checked(big);
  ASSERT_EQ(r.errors.size(), 1u);
  EXPECT_NE(r.errors[0].message.find("file too large"), std::string::npos);
}

}  // namespace
}  // namespace acdr
