// Keeps scenarios/scenario.schema.json in step with the loader: both are walked and compared
// key by key (path, JSON type, required, alternative unit spellings, bounds, item counts,
// allowed values), and the schema must describe every key.
#include <cmath>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "assessment/metric_catalog.hpp"
#include "scenarios/device_presets.hpp"
#include "scenarios/scenario_loader.hpp"
#include "tests/scenarios/scenario_test_support.hpp"

namespace acdr {
namespace {

using nlohmann::json;

/// A property of the schema with the object schema that holds it.
struct SchemaKey {
  const json* node;
  const json* parent;
  std::string name;
};

void walk(const json& object_schema, const std::string& pattern, std::map<std::string, SchemaKey>& out) {
  if (!object_schema.contains("properties")) return;
  for (auto it = object_schema["properties"].begin(); it != object_schema["properties"].end(); ++it) {
    const std::string p = pattern + "/" + it.key();
    out[p] = {&it.value(), &object_schema, it.key()};
    const json& node = it.value();
    if (node.value("type", json()) == "object") walk(node, p, out);
    if (node.value("type", json()) == "array" && node["items"].value("type", json()) == "object") {
      out[p + "/*"] = {&node["items"], nullptr, "*"};
      walk(node["items"], p + "/*", out);
    }
  }
}

std::string schema_type(const json& node) {
  const json& t = node.at("type");
  if (t.is_string()) return t.get<std::string>();
  std::string joined;
  for (const json& part : t) {
    if (!joined.empty()) joined += '|';
    joined += part.get<std::string>();
  }
  return joined;
}

bool contains_name(const json& list, const std::string& name) {
  for (const json& n : list) {
    if (n == name) return true;
  }
  return false;
}

/// Whether the object schema says "exactly one of" (required group) or "not both" (optional
/// group) for the spellings `names`.
bool states_group(const json& parent, const std::vector<std::string>& names, bool required) {
  if (!parent.contains("allOf")) return false;
  for (const json& rule : parent["allOf"]) {
    if (required && rule.contains("oneOf") && rule["oneOf"].size() == names.size()) {
      bool all = true;
      for (const std::string& n : names) {
        bool found = false;
        for (const json& alt : rule["oneOf"]) found = found || contains_name(alt["required"], n);
        all = all && found;
      }
      if (all) return true;
    }
    if (!required && rule.contains("not")) {
      bool all = true;
      for (const std::string& n : names) all = all && contains_name(rule["not"]["required"], n);
      if (all) return true;
    }
  }
  return false;
}

void expect_bound(const json& node, const char* name, const std::optional<double>& loader,
                  const std::string& where) {
  if (!loader) {
    EXPECT_FALSE(node.contains(name)) << where << ": schema has " << name << ", loader has none";
    return;
  }
  ASSERT_TRUE(node.contains(name)) << where << ": schema lacks " << name << " = " << *loader;
  const double s = node[name].get<double>();
  EXPECT_LE(std::fabs(s - *loader), 1e-9 * std::max(1.0, std::fabs(*loader)))
      << where << ": " << name << " schema " << s << " loader " << *loader;
}

class ScenarioSchema : public ::testing::Test {
 protected:
  void SetUp() override {
    schema_ = json::parse(test::read_text(test::source_path("scenarios/scenario.schema.json")));
    walk(schema_, "", schema_keys_);
    // The complete fixtures (one instrument, and the same scene with a tray) and the box module
    // between them reach every read of the loader.
    for (const char* file : {"tests/scenarios/data/complete.json", "tests/scenarios/data/complete_tray.json",
                             "scenarios/modules/01_box_warmup.json"}) {
      const LoadResult r = load_scenario_text(test::read_text(test::source_path(file)),
                                              test::source_path(file), &registry_);
      ASSERT_TRUE(r.ok()) << to_string(r.errors);
    }
  }
  json schema_;
  std::map<std::string, SchemaKey> schema_keys_;
  KeyRegistry registry_;
};

TEST_F(ScenarioSchema, IsDraft202012AndClosed) {
  EXPECT_EQ(schema_["$schema"], "https://json-schema.org/draft/2020-12/schema");
  EXPECT_EQ(schema_["additionalProperties"], false);
  for (const auto& [pattern, key] : schema_keys_) {
    if (key.node->value("type", json()) == "object") {
      EXPECT_EQ(key.node->value("additionalProperties", json(true)), false) << pattern;
    }
  }
}

TEST_F(ScenarioSchema, HasTheSameKeysAsTheLoader) {
  for (const auto& [pattern, info] : registry_.keys()) {
    EXPECT_TRUE(schema_keys_.count(pattern)) << "loader reads " << pattern << ", schema lacks it";
  }
  for (const auto& [pattern, key] : schema_keys_) {
    EXPECT_TRUE(registry_.keys().count(pattern)) << "schema has " << pattern << ", loader does not read it";
  }
  EXPECT_GT(registry_.keys().size(), 60u);
}

TEST_F(ScenarioSchema, AgreesOnTypesRequiredBoundsAndValues) {
  for (const auto& [pattern, info] : registry_.keys()) {
    auto found = schema_keys_.find(pattern);
    if (found == schema_keys_.end()) continue;  // reported by the test above
    const json& node = *found->second.node;
    SCOPED_TRACE(pattern);
    EXPECT_EQ(schema_type(node), info.type);
    if (found->second.parent != nullptr) {
      const json& parent = *found->second.parent;
      const bool listed = parent.contains("required") && contains_name(parent["required"], found->second.name);
      EXPECT_EQ(listed, info.required);
      if (!info.alternatives.empty()) {
        std::vector<std::string> names = info.alternatives;
        names.push_back(found->second.name);
        EXPECT_TRUE(states_group(parent, names, info.group_required))
            << "schema does not state the spellings as " << (info.group_required ? "one of" : "not both");
      }
    }
    // Vectors carry their bounds on each component.
    const json& bounded = info.type == "array" && node.contains("items") ? node["items"] : node;
    expect_bound(bounded, "minimum", info.minimum, pattern);
    expect_bound(bounded, "maximum", info.maximum, pattern);
    expect_bound(bounded, "exclusiveMinimum", info.exclusive_minimum, pattern);
    expect_bound(bounded, "exclusiveMaximum", info.exclusive_maximum, pattern);
    if (info.min_items) {
      EXPECT_EQ(node.value("minItems", json()), *info.min_items);
    }
    if (info.max_items) {
      EXPECT_EQ(node.value("maxItems", json()), *info.max_items);
    }
    if (!info.enum_values.empty() && info.value_pattern.empty()) {
      EXPECT_EQ(node.value("enum", json()), json(info.enum_values));
    }
    // A fixed list plus a pattern: anyOf [{enum}, {pattern}].
    if (!info.value_pattern.empty()) {
      EXPECT_FALSE(node.contains("enum"));
      EXPECT_EQ(node.value("anyOf", json()),
                json::array({{{"enum", info.enum_values}}, {{"pattern", info.value_pattern}}}));
    }
  }
}

TEST_F(ScenarioSchema, EnumsMatchTheLoadersTables) {
  std::vector<std::string> presets;
  for (const DevicePreset& p : device_presets()) presets.emplace_back(p.name);
  EXPECT_EQ(schema_["properties"]["world"]["properties"]["device"]["properties"]["preset"]["enum"], json(presets));
  for (const char* list : {"terms", "gates"}) {
    const json& metric = schema_["properties"]["rubric"]["properties"][list]["items"]["properties"]["metric"];
    EXPECT_EQ(metric["anyOf"][0]["enum"], json(known_metric_names())) << list;
    EXPECT_EQ(metric["anyOf"][1]["pattern"], zone_metric_pattern()) << list;
  }
}

TEST_F(ScenarioSchema, DescribesEveryKey) {
  for (const auto& [pattern, key] : schema_keys_) {
    if (key.name == "*") continue;
    ASSERT_TRUE(key.node->contains("description")) << pattern;
    EXPECT_GT((*key.node)["description"].get<std::string>().size(), 10u) << pattern;
  }
}

}  // namespace
}  // namespace acdr
