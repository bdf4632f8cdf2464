// Parsing of verification case files: JSON -> VerificationCaseSpec, with located errors.
#include "scenarios/verification_case_file.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "engine/core/input_file.hpp"
#include "scenarios/json_position_index.hpp"
#include "scenarios/key_suggestion.hpp"

namespace acdr {
namespace {

using json = nlohmann::json;

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) out += (i ? ", " : "") + names[i];
  return out;
}

std::string describe(const json& v) {
  if (v.is_string()) return "\"" + v.get<std::string>().substr(0, 40) + "\"";
  if (v.is_object()) return "an object";
  if (v.is_array()) return "an array";
  if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
  if (v.is_null()) return "null";
  return v.dump();
}

/// Parameters that must be strictly positive (a zero step or spacing has no meaning).
bool must_be_positive(const std::string& name) {
  return name == "dt_s" || name == "spacing_m" || name == "density_kg_m3";
}

class Reader {
 public:
  Reader(const std::string& path, const JsonPositionIndex& index, std::vector<ScenarioError>& errors)
      : path_(path), index_(index), errors_(errors) {}

  void error(const std::string& pointer, const std::string& message) {
    const TextPosition at = index_.find(pointer);
    errors_.push_back({path_, at.line, at.column, pointer, message});
  }

  void read_case(const json& c, const std::string& ptr, bool fast,
                 std::vector<VerificationCaseSpec>& out) {
    if (!c.is_object()) {
      error(ptr, "a case must be an object (got " + describe(c) +
                     ", expected {\"case\": ..., \"parameters\": {...}})");
      return;
    }
    const auto kinds = verification_case_kinds();
    if (!c.contains("case") || !c["case"].is_string()) {
      error(ptr + (c.contains("case") ? "/case" : ""),
            "missing or non-string \"case\" (expected one of: " + join(kinds) + ")");
      return;
    }
    const std::string kind = c["case"].get<std::string>();
    VerificationCaseSpec spec = default_verification_case(kind, fast);
    if (spec.kind.empty()) {
      const auto near = nearest_key(kind, kinds);
      error(ptr + "/case", "unknown case \"" + kind + "\" (expected one of: " + join(kinds) + ")" +
                               (near ? "; did you mean \"" + *near + "\"?" : ""));
      return;
    }
    for (auto it = c.begin(); it != c.end(); ++it) {
      const std::string& key = it.key();
      if (key == "case" || key == "parameters" || key == "name") continue;
      error(ptr + "/" + key,
            "unknown key \"" + key + "\" (expected \"case\", \"name\" or \"parameters\")");
    }
    if (c.contains("name")) {
      if (c["name"].is_string()) spec.name = c["name"].get<std::string>();
      else error(ptr + "/name", "name must be a string (got " + describe(c["name"]) + ")");
    }
    if (c.contains("parameters")) {
      const json& params = c["parameters"];
      if (!params.is_object()) {
        error(ptr + "/parameters",
              "parameters must be an object of numbers (got " + describe(params) + ")");
      } else {
        std::vector<std::string> names;
        for (const auto& p : spec.params) names.push_back(p.name);
        for (auto it = params.begin(); it != params.end(); ++it) {
          const std::string pp = ptr + "/parameters/" + it.key();
          if (!it.value().is_number()) {
            error(pp, "must be a number (got " + describe(it.value()) + ")");
            continue;
          }
          const double v = it.value().get<double>();
          const bool positive = must_be_positive(it.key());
          if (!std::isfinite(v) || v < 0.0 || (positive && v <= 0.0)) {
            error(pp, "out of range (got " + it.value().dump() + ", expected a finite number " +
                          (positive ? "> 0" : ">= 0") + ")");
            continue;
          }
          if (!spec.set(it.key(), v)) {
            const auto near = nearest_key(it.key(), names);
            error(pp, "unknown parameter \"" + it.key() + "\" for case " + kind +
                          " (expected one of: " + join(names) + ")" +
                          (near ? "; did you mean \"" + *near + "\"?" : ""));
          }
        }
      }
    }
    out.push_back(std::move(spec));
  }

 private:
  const std::string& path_;
  const JsonPositionIndex& index_;
  std::vector<ScenarioError>& errors_;
};

}  // namespace

VerificationCaseFile parse_verification_case_file(const std::string& text,
                                                  const std::string& path, bool fast) {
  VerificationCaseFile out;
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    const JsonPositionIndex lines = JsonPositionIndex::lines_only(text);
    std::size_t offset = 0;
    if (const auto* pe = dynamic_cast<const json::parse_error*>(&e))
      offset = pe->byte == 0 ? 0 : std::min<std::size_t>(pe->byte - 1, text.size());
    const TextPosition at = lines.position_of_offset(offset);
    out.errors.push_back({path, at.line, at.column, "",
                          std::string("malformed JSON: ") + e.what() +
                              " (expected a JSON object with \"cases\")"});
    return out;
  }
  const JsonPositionIndex index(text);
  Reader reader(path, index, out.errors);
  if (doc.is_object() && doc.contains("cases")) {
    for (auto it = doc.begin(); it != doc.end(); ++it)
      if (it.key() != "cases")
        reader.error("/" + it.key(), "unknown key \"" + it.key() + "\" (expected \"cases\")");
    const json& cases = doc["cases"];
    if (!cases.is_array() || cases.empty()) {
      reader.error("/cases", "\"cases\" must be a non-empty array (got " + describe(cases) + ")");
      return out;
    }
    for (std::size_t i = 0; i < cases.size(); ++i)
      reader.read_case(cases[i], "/cases/" + std::to_string(i), fast, out.cases);
  } else if (doc.is_object() && doc.contains("case")) {
    reader.read_case(doc, "", fast, out.cases);
  } else {
    reader.error("", "expected an object with \"cases\": [...] or a single \"case\" (got " +
                         describe(doc) + ")");
  }
  if (!out.ok()) out.cases.clear();
  return out;
}

VerificationCaseFile load_verification_case_file(const std::string& path, bool fast) {
  std::string error;
  const auto text = read_input_file(path, kMaxCaseFileBytes, "a verification case file (JSON)", &error);
  if (!text) {
    VerificationCaseFile out;
    out.errors.push_back({path, 0, 0, "", error});
    return out;
  }
  return parse_verification_case_file(*text, path, fast);
}

}  // namespace acdr
