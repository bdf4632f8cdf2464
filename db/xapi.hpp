// Export of attempts as xAPI 1.0.3 statements following the cmi5 rules (docs/references.md,
// "Training-record standards"), for a learning record store.
//
// Per completed, non-practice attempt, in start order:
// - `scored` (a cmi5 "allowed" statement): result.score {scaled = score/100 in 0..1, raw =
//   score, min 0, max 100}, success, completion true, duration, and every metric as a
//   result extension keyed by an IRI;
// - `passed` for the first passing attempt of its registration (cmi5 9.3.4: at most one per AU
//   and registration) or `failed` for each failing attempt (cmi5 9.3.5). These are cmi5
//   "defined" statements: cmi5 category, moveOn category, masteryScore = pass_score/100 in
//   context extensions, result.score {scaled} only (cmi5 9.5.1 wants an integer raw), success,
//   duration, no completion (9.5.3). When a safety gate failed an attempt whose score was above
//   the pass line, the verb would contradict masteryScore (9.3.5), so that statement carries no
//   masteryScore and names the reasons in a result extension instead.
// Practice attempts have no learner and are not exported; running and aborted attempts have no
// judged result (cmi5 forbids a score on `abandoned`) and are not exported either.
//
// Common to all: an opaque account actor (the trainee id), ADL verb IRIs, one activity IRI per
// module, context.registration, context.revision = scenario hash, context.platform = input
// device, the cmi5 session id = the attempt UUID, the instructor who overrode a lock as
// context.instructor, timestamp = end time, and a name-based (v5) statement id so re-exporting
// gives the same ids.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "db/records.hpp"

namespace acdr {

struct XapiOptions {
  /// Prefix of every IRI we mint (activities, extensions). Set it to a domain you control;
  /// the default uses the reserved documentation TLD ".example".
  std::string base_iri = "https://acdr.example/xapi/";
  /// homePage of the trainees' accounts (the system that issued the opaque ids).
  std::string account_home_page = "https://acdr.example/trainees";
  /// Language tag of display texts.
  std::string language = "en-US";
};

/// The IRI of a module's activity: base_iri + "modules/" + percent-encoded id.
std::string xapi_activity_iri(const XapiOptions& options, const std::string& module_id);
/// The result-extension IRI of a metric: base_iri + "metrics/" + percent-encoded name.
std::string xapi_metric_iri(const XapiOptions& options, const std::string& metric_name);

/// One statement of the export: its id, the attempt it reports and its JSON (one line).
struct XapiStatement {
  std::string id;            ///< the statement id (a v5 UUID from the attempt and the verb)
  std::string attempt_uuid;  ///< the attempt it reports
  std::string json;          ///< the statement object, compact
};

/// The statements for `attempts`, one by one, in the order of xapi_statements_json (same
/// preconditions).
std::vector<XapiStatement> xapi_statements(const std::vector<AttemptRecord>& attempts,
                                           const std::map<std::string, ModuleRecord>& modules,
                                           const XapiOptions& options = {});

/// The statements (a JSON array, pretty-printed) for `attempts`, which must be in start order
/// and contain every attempt of each registration they touch (any trainee/module filter
/// does). `modules` gives titles and pass scores by module id.
std::string xapi_statements_json(const std::vector<AttemptRecord>& attempts,
                                 const std::map<std::string, ModuleRecord>& modules,
                                 const XapiOptions& options = {});

}  // namespace acdr
