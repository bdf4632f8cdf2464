// xAPI / cmi5 export: see xapi.hpp for which statements and why.
#include "db/xapi.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>

#include <nlohmann/json.hpp>

#include "db/utc_time.hpp"
#include "db/uuid.hpp"

namespace acdr {

namespace {

using Json = nlohmann::ordered_json;

// Namespace of our v5 statement ids (itself a fixed random UUID; never change it, or
// re-exports stop matching earlier ones).
constexpr const char* kStatementNamespace = "5d3c8f0e-8a41-4c1b-9f0a-2b7e6d9c4a13";

// ADL verb IRIs (http://adlnet.gov/expapi/verbs/...), as cmi5 9.3 uses them.
constexpr const char* kVerbScored = "http://adlnet.gov/expapi/verbs/scored";
constexpr const char* kVerbPassed = "http://adlnet.gov/expapi/verbs/passed";
constexpr const char* kVerbFailed = "http://adlnet.gov/expapi/verbs/failed";
constexpr const char* kActivityTypeSimulation = "http://adlnet.gov/expapi/activities/simulation";
constexpr const char* kCmi5Category = "https://w3id.org/xapi/cmi5/context/categories/cmi5";
constexpr const char* kMoveOnCategory = "https://w3id.org/xapi/cmi5/context/categories/moveon";
constexpr const char* kSessionIdExt = "https://w3id.org/xapi/cmi5/context/extensions/sessionid";
constexpr const char* kMasteryScoreExt =
    "https://w3id.org/xapi/cmi5/context/extensions/masteryscore";

// RFC 3986 unreserved characters pass; everything else is %XX (UTF-8 bytes).
std::string percent_encode(const std::string& text) {
  static const char* kHex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : text) {
    if (std::isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~') {
      out.push_back(static_cast<char>(c));
    } else {
      out.push_back('%');
      out.push_back(kHex[c >> 4]);
      out.push_back(kHex[c & 0xF]);
    }
  }
  return out;
}

std::string with_slash(const std::string& base) {
  return (!base.empty() && base.back() == '/') ? base : base + "/";
}

Json number_or_null(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }

double attempt_duration_s(const AttemptRecord& a) {
  if (a.duration_s && std::isfinite(*a.duration_s)) return *a.duration_s;
  // No simulated duration stored: fall back to the wall-clock time between start and end.
  std::optional<UtcTime> start = parse_utc(a.started_utc);
  std::optional<UtcTime> end = a.ended_utc ? parse_utc(*a.ended_utc) : std::nullopt;
  if (!start || !end) return 0.0;
  return std::chrono::duration<double>(*end - *start).count();
}

Json verb(const char* iri, const char* word, const XapiOptions& options) {
  return Json{{"id", iri}, {"display", Json{{options.language, word}}}};
}

Json account_agent(const std::string& name, const XapiOptions& options) {
  return Json{{"objectType", "Agent"},
              {"account", Json{{"homePage", options.account_home_page}, {"name", name}}}};
}

}  // namespace

std::string xapi_activity_iri(const XapiOptions& options, const std::string& module_id) {
  return with_slash(options.base_iri) + "modules/" + percent_encode(module_id);
}

std::string xapi_metric_iri(const XapiOptions& options, const std::string& metric_name) {
  return with_slash(options.base_iri) + "metrics/" + percent_encode(metric_name);
}

namespace {

// One built statement and the uuid of the attempt it reports.
struct BuiltStatement {
  std::string attempt_uuid;
  Json statement;
};

std::vector<BuiltStatement> build_statements(const std::vector<AttemptRecord>& attempts,
                                             const std::map<std::string, ModuleRecord>& modules,
                                             const XapiOptions& options) {
  const std::string base = with_slash(options.base_iri);
  std::vector<BuiltStatement> statements;
  std::set<std::pair<std::string, std::string>> passed_registrations;  // (registration, module)

  for (const AttemptRecord& a : attempts) {
    if (a.is_practice() || a.status != AttemptStatus::kCompleted || !a.passed) continue;
    const auto module_it = modules.find(a.module_id);
    const ModuleRecord* module = module_it == modules.end() ? nullptr : &module_it->second;
    const double score = a.score.value_or(0.0);
    const double scaled = std::clamp(std::isfinite(score) ? score / 100.0 : 0.0, 0.0, 1.0);
    const bool passed = *a.passed;
    const std::string duration = iso8601_duration(attempt_duration_s(a));
    const std::string timestamp = a.ended_utc.value_or(a.started_utc);

    Json object{{"objectType", "Activity"}, {"id", xapi_activity_iri(options, a.module_id)}};
    Json definition{{"type", kActivityTypeSimulation}};
    if (module && !module->title.empty()) {
      definition["name"] = Json{{options.language, module->title}};
    }
    object["definition"] = definition;

    // Context shared by every statement of this attempt.
    Json context{{"registration", a.registration}};
    if (!a.scenario_hash.empty()) context["revision"] = a.scenario_hash;
    if (!a.input_device.empty()) context["platform"] = a.input_device;
    if (a.override_lock) context["instructor"] = account_agent(a.override_by, options);
    Json context_ext{{kSessionIdExt, a.uuid}};
    if (!a.program_version.empty()) context_ext[base + "extensions/program-version"] =
        a.program_version;
    if (a.override_lock) {
      context_ext[base + "extensions/override"] =
          Json{{"by", a.override_by}, {"reason", a.override_reason}};
    }
    if (module && module->curriculum_id) {
      context["contextActivities"] = Json{
          {"parent", Json::array({Json{{"objectType", "Activity"},
                                       {"id", base + "curricula/" +
                                                  percent_encode(*module->curriculum_id)}}})}};
    }

    auto make_statement = [&](const char* verb_iri, const char* verb_word, Json result,
                              Json statement_context) {
      return Json{{"id", *make_uuid_v5(kStatementNamespace, a.uuid + "/" + verb_word)},
                  {"actor", account_agent(*a.trainee_id, options)},
                  {"verb", verb(verb_iri, verb_word, options)},
                  {"object", object},
                  {"result", std::move(result)},
                  {"context", std::move(statement_context)},
                  {"timestamp", timestamp}};
    };

    // 1. scored: the full result, metrics as extensions.
    {
      Json result{{"score", Json{{"scaled", scaled},
                                 {"raw", std::clamp(std::isfinite(score) ? score : 0.0, 0.0,
                                                    100.0)},
                                 {"min", 0},
                                 {"max", 100}}},
                  {"success", passed},
                  {"completion", true},
                  {"duration", duration}};
      Json extensions = Json::object();
      for (const auto& [name, value] : a.metrics.values) {
        extensions[xapi_metric_iri(options, name)] = number_or_null(value);
      }
      if (!a.score_detail.reasons.empty()) {
        extensions[base + "extensions/fail-reasons"] = a.score_detail.reasons;
      }
      if (!extensions.empty()) result["extensions"] = extensions;
      Json ctx = context;
      ctx["extensions"] = context_ext;
      statements.push_back(
          {a.uuid, make_statement(kVerbScored, "scored", std::move(result), ctx)});
    }

    // 2. passed (once per registration and module) or failed.
    const bool first_pass =
        passed && passed_registrations.insert({a.registration, a.module_id}).second;
    if (passed && !first_pass) continue;
    Json result{{"score", Json{{"scaled", scaled}}}, {"success", passed}, {"duration", duration}};
    Json ctx = context;
    ctx["contextActivities"]["category"] =
        Json::array({Json{{"id", kCmi5Category}}, Json{{"id", kMoveOnCategory}}});
    Json ext = context_ext;
    const double mastery = module ? std::clamp(module->pass_score / 100.0, 0.0, 1.0) : 0.5;
    // cmi5: passed needs scaled >= masteryScore, failed needs scaled < masteryScore. A safety
    // gate can fail an attempt scoring above the line; then masteryScore is left out rather
    // than contradicted.
    const bool consistent = passed ? scaled >= mastery : scaled < mastery;
    if (consistent) {
      ext[kMasteryScoreExt] = mastery;
    } else if (!a.score_detail.reasons.empty()) {
      result["extensions"] =
          Json{{base + "extensions/fail-reasons", a.score_detail.reasons}};
    }
    ctx["extensions"] = ext;
    statements.push_back(
        {a.uuid, passed ? make_statement(kVerbPassed, "passed", std::move(result), ctx)
                        : make_statement(kVerbFailed, "failed", std::move(result), ctx)});
  }
  return statements;
}

}  // namespace

std::vector<XapiStatement> xapi_statements(const std::vector<AttemptRecord>& attempts,
                                           const std::map<std::string, ModuleRecord>& modules,
                                           const XapiOptions& options) {
  std::vector<XapiStatement> out;
  for (BuiltStatement& built : build_statements(attempts, modules, options)) {
    out.push_back(XapiStatement{built.statement["id"].get<std::string>(),
                                std::move(built.attempt_uuid),
                                built.statement.dump(-1, ' ', false,
                                                     Json::error_handler_t::replace)});
  }
  return out;
}

std::string xapi_statements_json(const std::vector<AttemptRecord>& attempts,
                                 const std::map<std::string, ModuleRecord>& modules,
                                 const XapiOptions& options) {
  Json statements = Json::array();
  for (BuiltStatement& built : build_statements(attempts, modules, options)) {
    statements.push_back(std::move(built.statement));
  }
  // Invalid UTF-8 in stored text must not abort the export: replace it with U+FFFD.
  return statements.dump(2, ' ', false, Json::error_handler_t::replace);
}

}  // namespace acdr
