// Whatever validates runs: for every numeric key of scenarios/scenario.schema.json, a bundled
// module with that one key set to its documented minimum, then to its maximum (every component,
// for vectors), either is refused by `acdr validate` or completes `acdr run --headless` on a
// 0.1 s trajectory; each under a 4 GB address-space limit (`ulimit -v 4000000`), ending by
// itself, never by a signal. One spelling per quantity is walked (dt_ms, not also dt_s: the
// loader converts both to the same SI bound, and the schema test checks that they agree).
// The vertebra's own dimensions (morphometry) are run together: each extreme that validates
// alone joins the first group of extremes it still validates with, and each group is one run,
// because every run remeshes both vertebrae and rebuilds their grids and bone model (5-15 s
// apiece here); so every extreme that validates is run, in a handful of runs instead of fifty.
// The walk is split into shards that ctest runs side by side (ACDR_BOUNDS_SHARD=k/n: the
// extremes whose ordinal is k modulo n; tests/cli/CMakeLists.txt), so a loaded machine does not
// push one long test past its timeout.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/cli/acdr_process.hpp"

namespace acdr {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string source(const std::string& relative) { return std::string(ACDR_SOURCE_DIR) + "/" + relative; }

/// One numeric key of the schema: its pattern ("/world/solver/dt_ms", "*" for array items),
/// bounds, and whether it is an integer or a 3-vector.
struct NumericKey {
  std::string pattern;
  std::string name;
  bool integer = false;
  bool vector = false;
  std::optional<double> min, max;
  bool min_exclusive = false, max_exclusive = false;
};

/// The quantity a key spells (its name less a unit suffix), to walk one spelling of each.
std::string quantity_of(const std::string& name) {
  for (const char* unit : {"_mm_s", "_m_s", "_mm", "_m", "_g", "_kg", "_MPa", "_kPa", "_Pa", "_ms", "_s"}) {
    const std::string u = unit;
    if (name.size() > u.size() && name.compare(name.size() - u.size(), u.size(), u) == 0) {
      return name.substr(0, name.size() - u.size());
    }
  }
  return name;
}

void bounds_of(const json& node, NumericKey& k) {
  if (node.contains("minimum")) k.min = node["minimum"].get<double>();
  if (node.contains("maximum")) k.max = node["maximum"].get<double>();
  if (node.contains("exclusiveMinimum")) k.min = node["exclusiveMinimum"].get<double>(), k.min_exclusive = true;
  if (node.contains("exclusiveMaximum")) k.max = node["exclusiveMaximum"].get<double>(), k.max_exclusive = true;
}

void walk(const json& object_schema, const std::string& pattern, std::vector<NumericKey>& out) {
  if (!object_schema.contains("properties")) return;
  std::vector<std::string> quantities;
  for (auto it = object_schema["properties"].begin(); it != object_schema["properties"].end(); ++it) {
    const std::string p = pattern + "/" + it.key();
    const json& node = it.value();
    const json type = node.value("type", json());
    if (type == "object") walk(node, p, out);
    // A tray's instruments are read as /world/instrument is (the same keys and bounds), which
    // this walk already reaches.
    if (type == "array" && node.contains("items") && node["items"].value("type", json()) == "object" &&
        p != "/world/instruments") {
      walk(node["items"], p + "/*", out);
    }
    NumericKey k;
    k.pattern = p;
    k.name = it.key();
    if (type == "number" || type == "integer") {
      k.integer = type == "integer";
      bounds_of(node, k);
    } else if (type == "array" && node.value("minItems", 0) == 3 && node.contains("items") &&
               node["items"].value("type", json()) == "number") {
      k.vector = true;
      bounds_of(node["items"], k);
    }
    if (!k.min && !k.max) continue;
    if (k.name == "format_version") continue;  // one value only, checked elsewhere
    const std::string q = quantity_of(k.name);
    if (std::find(quantities.begin(), quantities.end(), q) != quantities.end()) continue;
    quantities.push_back(q);
    out.push_back(k);
  }
}

/// The base file for a key: the C4-C5 module for anatomy (with one extra zone to reach the
/// zone keys), the box module for the rest.
json base_for(const std::string& pattern) {
  const bool anatomy = pattern.rfind("/world/anatomy", 0) == 0;
  json doc = json::parse(read_text(source(anatomy ? "scenarios/modules/02_c4c5_healthy.json"
                                                  : "scenarios/modules/01_box_warmup.json")));
  doc.erase("$schema");
  if (anatomy) {
    doc["world"]["anatomy"]["zones"]["extra"] = json::array(
        {{{"name", "probe"}, {"shape", "sphere"}, {"a_mm", {0, 0, -30}}, {"radius_mm", 1}, {"warning_mm", 1},
          {"force_limit_N", 1}, {"never_event", false}}});
  }
  return doc;
}

/// `doc` with the key at `pattern` (items: the first) set to `value`, other spellings of the
/// same quantity removed, and missing objects on the way created.
void set_key(json& doc, const NumericKey& k, const json& value) {
  json* at = &doc;
  std::stringstream parts(k.pattern.substr(1));
  std::vector<std::string> tokens;
  for (std::string t; std::getline(parts, t, '/');) tokens.push_back(t);
  for (std::size_t i = 0; i + 1 < tokens.size(); ++i) {
    if (tokens[i] == "*") {
      at = &(*at)[0];
    } else {
      if (!at->contains(tokens[i])) (*at)[tokens[i]] = json::object();
      at = &(*at)[tokens[i]];
    }
  }
  const std::string q = quantity_of(k.name);
  for (auto it = at->begin(); it != at->end();) {
    if (it.key() != k.name && quantity_of(it.key()) == q && it.key() != q) it = at->erase(it);
    else ++it;
  }
  (*at)[k.name] = value;
}

/// A 0.1 s trajectory holding the instrument where the scenario starts it.
std::string write_trajectory(const json& doc, const std::string& path) {
  std::vector<double> p = {0, 0, 0.11};
  if (doc["world"].contains("instrument_start") && doc["world"]["instrument_start"].contains("position_mm")) {
    p = doc["world"]["instrument_start"]["position_mm"].get<std::vector<double>>();
    for (double& x : p) x *= 1e-3;
  }
  std::ofstream out(path);
  out << "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";
  for (double t : {0.0, 0.1}) out << t << "," << p[0] << "," << p[1] << "," << p[2] << ",1,0,0,0\n";
  return path;
}

TEST(AcdrSchemaBounds, EveryExtremeIsRefusedOrRunsWithinFourGigabytes) {
  const json schema = json::parse(read_text(source("scenarios/scenario.schema.json")));
  std::vector<NumericKey> keys;
  walk(schema, "", keys);
  ASSERT_GT(keys.size(), 80u);

  const fs::path dir = fs::temp_directory_path() / ("acdr_schema_bounds_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // Meshes and grids cached in a directory of the test's own, shared by its runs.
  ::setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);

  // This shard: the extremes whose ordinal is k modulo n (all of them without the variable).
  int shard = 0, shards = 1;
  if (const char* s = std::getenv("ACDR_BOUNDS_SHARD")) {
    ASSERT_EQ(std::sscanf(s, "%d/%d", &shard, &shards), 2) << "ACDR_BOUNDS_SHARD=" << s;
    ASSERT_TRUE(shards >= 1 && shard >= 0 && shard < shards) << "ACDR_BOUNDS_SHARD=" << s;
  }
  int ordinal = -1;
  int refused = 0, ran = 0, failed_numerically = 0, extremes_run = 0;
  double slowest = 0.0;
  std::string slowest_case;
  const std::string scenario = (dir / "scenario.json").string();
  auto validates = [&](const json& doc) {
    std::ofstream(scenario) << doc.dump(2);
    const test::ProcessResult v_run = test::run_process({ACDR_EXE, "validate", scenario}, test::kFourGigabytes, 60.0);
    EXPECT_FALSE(v_run.timed_out) << v_run.output;
    EXPECT_EQ(v_run.signal, 0) << v_run.output;
    EXPECT_TRUE(v_run.exit_code == 0 || v_run.exit_code == 1) << "exit " << v_run.exit_code << "\n" << v_run.output;
    return v_run.exit_code == 0;
  };
  // Runs `doc` (which validates) headless on a 0.1 s trajectory within 4 GB.
  auto run_ok = [&](const json& doc, const std::string& what) {
    SCOPED_TRACE(what);
    std::ofstream(scenario) << doc.dump(2);
    const std::string trajectory = write_trajectory(doc, (dir / "short.csv").string());
    const test::ProcessResult r = test::run_process(
        {ACDR_EXE, "run", scenario, "--input", "replay:" + trajectory, "--headless", "--db",
         (dir / "record.db").string(), "--checkpoint-every", "0"},
        test::kFourGigabytes, 300.0);
    EXPECT_FALSE(r.timed_out) << r.output;
    EXPECT_EQ(r.signal, 0) << r.output;
    // Completed (0) or stopped by a numerical failure (1, stored as completed).
    EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 1) << "exit " << r.exit_code << "\n" << r.output;
    ++ran;
    failed_numerically += r.exit_code == 1;
    if (r.seconds > slowest) slowest = r.seconds, slowest_case = what;
  };
  struct ShapeExtreme {
    NumericKey key;
    json value;
    std::string what;
  };
  std::vector<ShapeExtreme> shapes;
  for (const NumericKey& k : keys) {
    for (int end = 0; end < 2; ++end) {
      const std::optional<double>& bound = end == 0 ? k.min : k.max;
      if (!bound) continue;
      if (++ordinal % shards != shard) continue;
      double v = *bound;
      const bool exclusive = end == 0 ? k.min_exclusive : k.max_exclusive;
      if (exclusive) v = std::nextafter(v, end == 0 ? INFINITY : -INFINITY);
      const json value = k.integer ? json(static_cast<long long>(std::llround(v)))
                         : k.vector ? json::array({v, v, v})
                                    : json(v);
      const std::string what = k.pattern + " = " + value.dump();
      SCOPED_TRACE(what);
      json doc = base_for(k.pattern);
      set_key(doc, k, value);
      if (!validates(doc)) {
        ++refused;
        continue;
      }
      const bool shape = k.pattern.rfind("/world/anatomy/morphometry/", 0) == 0 &&
                         k.name.rfind("mesh_spacing", 0) != 0;
      if (shape) {
        shapes.push_back({k, value, what});
        continue;
      }
      run_ok(doc, what);
      ++extremes_run;
    }
  }
  // The valid shape extremes, grouped: each joins the first group that does not set its key
  // yet and that it still validates with.
  struct Group {
    json doc;
    std::vector<std::string> keys, names;
  };
  std::vector<Group> groups;
  for (const ShapeExtreme& e : shapes) {
    bool placed = false;
    for (Group& g : groups) {
      if (std::find(g.keys.begin(), g.keys.end(), e.key.pattern) != g.keys.end()) continue;
      json trial = g.doc;
      set_key(trial, e.key, e.value);
      if (validates(trial)) {
        g.doc = std::move(trial);
        g.keys.push_back(e.key.pattern);
        g.names.push_back(e.what);
        placed = true;
        break;
      }
    }
    if (!placed) {
      json doc = base_for(e.key.pattern);
      set_key(doc, e.key, e.value);
      groups.push_back({std::move(doc), {e.key.pattern}, {e.what}});
    }
  }
  for (const auto& [doc, keys_set, names] : groups) {
    std::string what = "morphometry group:";
    for (const std::string& n : names) what += "\n  " + n;
    run_ok(doc, what);
    extremes_run += static_cast<int>(names.size());
  }
  EXPECT_GT(refused + extremes_run, 0) << "shard " << shard << "/" << shards << " walked nothing";
  std::cout << "shard " << shard << "/" << shards << ": " << keys.size() << " numeric keys, "
            << refused + extremes_run << " extremes: " << refused
            << " refused by validate, " << extremes_run << " ran (" << shapes.size() << " vertebra shapes in "
            << groups.size() << " runs), " << ran << " runs (" << failed_numerically
            << " ended in a numerical failure); slowest run " << slowest << " s (" << slowest_case << ")\n";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace acdr
