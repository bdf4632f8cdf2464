// Reports of the record for instructors: attempts (filtered by trainee and/or module) with
// scores and key metrics, and each trainee's progress through the curriculum, as an aligned
// text table, CSV (RFC 4180), JSON, or xAPI statements (xapi.hpp).
#pragma once

#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "db/attempt_store.hpp"
#include "db/database.hpp"
#include "db/progression.hpp"
#include "db/records.hpp"
#include "db/xapi.hpp"

namespace acdr {

enum class ReportFormat { kTable, kCsv, kJson, kXapi };

/// "table", "csv", "json", "xapi" (what `acdr report --format` accepts).
std::optional<ReportFormat> parse_report_format(std::string_view text);

struct ReportRequest {
  std::optional<std::string> trainee_id;  ///< only this trainee (and their progress)
  std::optional<std::string> module_id;   ///< only this module
  bool include_practice = true;           ///< practice attempts (not in xAPI in any case)
  ReportFormat format = ReportFormat::kTable;
  XapiOptions xapi;
};

/// Everything a report shows, read in one snapshot.
struct ReportData {
  std::optional<std::string> trainee_id;  ///< the request's filters, echoed
  std::optional<std::string> module_id;
  std::vector<AttemptRecord> attempts;  ///< start order, with metrics and events
  std::map<std::string, ModuleRecord> modules;
  /// Progress per trainee: the filtered trainee, or every trainee with a listed attempt.
  /// Restricted to the filtered module when there is one.
  std::map<std::string, std::vector<ModuleProgress>> progress;
};

DbResult<ReportData> collect_report(Database& db, const ReportRequest& request);

/// Aligned text for a terminal: attempts, then progress per trainee.
void write_report_table(const ReportData& data, std::ostream& out);
/// One row per attempt, CRLF line ends, fields quoted when they hold a comma, quote, CR or LF.
/// Metric columns are the union of metric names in first-seen order. Text cells that a
/// spreadsheet would run as a formula (starting with = + - @ or a tab) get a leading "'".
void write_report_csv(const ReportData& data, std::ostream& out);
/// {"format": "acdr-report", "version": 1, "attempts": [...], "progress": [...]}.
void write_report_json(const ReportData& data, std::ostream& out);
/// xapi_statements_json over the report's attempts.
void write_report_xapi(const ReportData& data, const XapiOptions& options, std::ostream& out);

/// collect_report, then the requested format.
DbStatus write_report(Database& db, const ReportRequest& request, std::ostream& out);

}  // namespace acdr
