// Reports in table, CSV, JSON and xAPI form: see report.hpp.
#include "db/report.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <set>

#include <nlohmann/json.hpp>

#include "db/catalog.hpp"

namespace acdr {

namespace {

using Json = nlohmann::ordered_json;

// Metrics worth a column in the terminal table when present (the first metrics);
// CSV and JSON carry all of them.
constexpr const char* kKeyMetrics[] = {"nucleus_removed_fraction", "peak_instrument_force_N",
                                       "peak_bending_moment_Nm", "overload_events"};

// Shortest text that reads back as the same double (std::to_chars).
std::string exact_number(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "Infinity" : "-Infinity";
  char buffer[64];
  auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return ec == std::errc() ? std::string(buffer, end) : std::string("NaN");
}

// A CSV cell: nine significant digits, trailing zeros dropped (9.800000000000008 -> 9.8), so
// the sums of many 1 ms steps read as the figures they are; nine digits keep every metric's
// resolution (the recording keeps the exact values).
std::string csv_number(double value) {
  if (!std::isfinite(value)) return exact_number(value);
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.9g", value);
  return buffer;
}

std::string fixed(double value, int decimals) {
  if (!std::isfinite(value)) return exact_number(value);
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

std::string short_number(double value) {
  if (!std::isfinite(value)) return exact_number(value);
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.4g", value);
  return buffer;
}

std::string result_word(const AttemptRecord& a) {
  if (a.status != AttemptStatus::kCompleted || !a.passed) return "-";
  return *a.passed ? "pass" : "FAIL";
}

// Display width of UTF-8 text in code points (good enough to align ids and names).
std::size_t display_width(const std::string& text) {
  std::size_t width = 0;
  for (unsigned char c : text) {
    if ((c & 0xC0) != 0x80) ++width;
  }
  return width;
}

// Control characters as visible escapes (a newline shows as backslash-n).
std::string printable(const std::string& text) {
  std::string out;
  for (unsigned char c : text) {
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c < 0x20 || c == 0x7F) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\x%02x", c);
      out += buffer;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out;
}

// An aligned text table: columns padded to their widest cell, numbers right-aligned.
class TextTable {
 public:
  TextTable(std::vector<std::string> headers, std::vector<bool> right_aligned)
      : headers_(std::move(headers)), right_(std::move(right_aligned)) {}
  void add(std::vector<std::string> row) {
    // A newline or tab inside a stored id would break the layout: show it escaped.
    for (std::string& cell : row) cell = printable(cell);
    rows_.push_back(std::move(row));
  }

  void print(std::ostream& out) const {
    std::vector<std::size_t> width(headers_.size());
    for (std::size_t c = 0; c < headers_.size(); ++c) width[c] = display_width(headers_[c]);
    for (const auto& row : rows_) {
      for (std::size_t c = 0; c < row.size() && c < width.size(); ++c) {
        width[c] = std::max(width[c], display_width(row[c]));
      }
    }
    auto line = [&](const std::vector<std::string>& cells) {
      std::string text;
      for (std::size_t c = 0; c < width.size(); ++c) {
        const std::string& cell = c < cells.size() ? cells[c] : std::string();
        const std::string pad(width[c] - display_width(cell), ' ');
        if (c > 0) text += "  ";
        text += right_[c] ? pad + cell : cell + pad;
      }
      while (!text.empty() && text.back() == ' ') text.pop_back();
      out << text << '\n';
    };
    line(headers_);
    std::vector<std::string> rule;
    for (std::size_t w : width) rule.emplace_back(w, '-');
    line(rule);
    for (const auto& row : rows_) line(row);
  }

 private:
  std::vector<std::string> headers_;
  std::vector<bool> right_;
  std::vector<std::vector<std::string>> rows_;
};

// RFC 4180 field: quoted when it contains a comma, a quote, CR or LF; quotes doubled.
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

// A text cell: defused against spreadsheet formula execution (CSV injection), then quoted.
std::string csv_text(const std::string& text) {
  if (!text.empty() && std::string_view("=+-@\t\r").find(text.front()) != std::string::npos) {
    return csv_field("'" + text);
  }
  return csv_field(text);
}

Json optional_number(const std::optional<double>& value) {
  return value ? Json(*value) : Json(nullptr);  // nlohmann writes NaN/Inf as null
}

Json optional_text(const std::optional<std::string>& value) {
  return value ? Json(*value) : Json(nullptr);
}

Json progress_json(const ModuleProgress& p) {
  return Json{{"module", p.module_id},
              {"title", p.title},
              {"curriculum", optional_text(p.curriculum_id)},
              {"position", p.position},
              {"state", p.state_name()},
              {"attempts", p.run.attempts},
              {"passes", p.run.passes},
              {"consecutive_passes", p.run.consecutive_at_end},
              {"consecutive_passes_required", p.required_consecutive},
              {"pass_score", p.pass_score},
              {"mastered", p.mastered},
              {"unlocked", p.unlocked},
              {"prerequisites", p.prerequisites},
              {"missing_prerequisites", p.missing_prerequisites},
              {"best_score", optional_number(p.best_score)},
              {"last_score", optional_number(p.last_score)}};
}

}  // namespace

std::optional<ReportFormat> parse_report_format(std::string_view text) {
  if (text == "table") return ReportFormat::kTable;
  if (text == "csv") return ReportFormat::kCsv;
  if (text == "json") return ReportFormat::kJson;
  if (text == "xapi") return ReportFormat::kXapi;
  return std::nullopt;
}

DbResult<ReportData> collect_report(Database& db, const ReportRequest& request) {
  // One read snapshot for attempts, modules and progress, even while an attempt is written.
  DbResult<Transaction> tx = Transaction::begin(db, Transaction::Mode::kDeferred);
  if (!tx) return tx.error();
  ReportData data;
  data.trainee_id = request.trainee_id;
  data.module_id = request.module_id;

  DbResult<std::vector<AttemptRecord>> attempts = list_attempts(
      db, AttemptFilter{request.trainee_id, request.module_id, request.include_practice},
      AttemptDetail{true, true, false});
  if (!attempts) return attempts.error();
  data.attempts = std::move(attempts.value());

  DbResult<std::vector<ModuleRecord>> modules = list_modules(db);
  if (!modules) return modules.error();
  for (ModuleRecord& m : modules.value()) data.modules.emplace(m.id, std::move(m));

  std::set<std::string> trainees;
  if (request.trainee_id) {
    trainees.insert(*request.trainee_id);
  } else {
    for (const AttemptRecord& a : data.attempts) {
      if (a.trainee_id) trainees.insert(*a.trainee_id);
    }
  }
  for (const std::string& trainee : trainees) {
    DbResult<std::vector<ModuleProgress>> progress = trainee_progress(db, trainee);
    if (!progress) return progress.error();
    std::vector<ModuleProgress> rows;
    for (ModuleProgress& p : progress.value()) {
      if (!request.module_id || p.module_id == *request.module_id) rows.push_back(std::move(p));
    }
    data.progress.emplace(trainee, std::move(rows));
  }
  if (DbStatus c = tx->commit(); !c) return c.error();
  return data;
}

void write_report_table(const ReportData& data, std::ostream& out) {
  // Key metric columns: those that at least one listed attempt has.
  std::vector<std::string> metric_columns;
  for (const char* name : kKeyMetrics) {
    for (const AttemptRecord& a : data.attempts) {
      if (std::any_of(a.metrics.values.begin(), a.metrics.values.end(),
                      [&](const auto& m) { return m.first == name; })) {
        metric_columns.emplace_back(name);
        break;
      }
    }
  }

  std::vector<std::string> headers = {"id",       "trainee",   "module", "started (UTC)",
                                      "status",   "score",     "result", "time (s)",
                                      "real time", "events"};
  std::vector<bool> right = {true, false, false, false, false, true, false, true, true, true};
  for (const std::string& name : metric_columns) {
    headers.push_back(name);
    right.push_back(true);
  }
  TextTable attempts(headers, right);
  for (const AttemptRecord& a : data.attempts) {
    std::vector<std::string> row = {
        std::to_string(a.id),
        a.trainee_id.value_or("(practice)"),
        a.module_id,
        a.started_utc.substr(0, 19),
        std::string(attempt_status_name(a.status)) + (a.override_lock ? " (override)" : ""),
        a.score ? fixed(*a.score, 1) : "-",
        result_word(a),
        a.duration_s ? fixed(*a.duration_s, 1) : "-",
        a.realtime_factor ? fixed(*a.realtime_factor, 2) + "x" : "-",
        std::to_string(a.events.size())};
    for (const std::string& name : metric_columns) {
      const auto it = std::find_if(a.metrics.values.begin(), a.metrics.values.end(),
                                   [&](const auto& m) { return m.first == name; });
      row.push_back(it == a.metrics.values.end() ? "-" : short_number(it->second));
    }
    attempts.add(std::move(row));
  }
  out << "Attempts (" << data.attempts.size() << ")\n";
  attempts.print(out);

  for (const auto& [trainee, modules] : data.progress) {
    out << "\nProgress of trainee " << printable(trainee) << "\n";
    TextTable progress({"module", "state", "attempts", "passes", "run", "needed", "best", "last",
                        "missing prerequisites"},
                       {false, false, true, true, true, true, true, true, false});
    for (const ModuleProgress& p : modules) {
      std::string missing;
      for (const std::string& id : p.missing_prerequisites) {
        if (!missing.empty()) missing += ", ";
        missing += id;
      }
      progress.add({p.module_id, p.state_name(), std::to_string(p.run.attempts),
                    std::to_string(p.run.passes), std::to_string(p.run.consecutive_at_end),
                    std::to_string(p.required_consecutive),
                    p.best_score ? fixed(*p.best_score, 1) : "-",
                    p.last_score ? fixed(*p.last_score, 1) : "-", missing});
    }
    progress.print(out);
  }
}

void write_report_csv(const ReportData& data, std::ostream& out) {
  std::vector<std::string> metric_names;
  std::set<std::string> seen;
  for (const AttemptRecord& a : data.attempts) {
    for (const auto& [name, value] : a.metrics.values) {
      if (seen.insert(name).second) metric_names.push_back(name);
    }
  }
  const char* kEol = "\r\n";  // RFC 4180 section 2.1
  const std::vector<std::string> fixed_columns = {
      "attempt_id",   "attempt_uuid",    "registration",  "trainee",      "module",
      "status",       "started_utc",     "ended_utc",     "duration_s",   "realtime_factor",
      "score",
      "passed",       "override",        "override_by",   "override_reason", "input_device",
      "program_version", "scenario_hash", "abort_reason", "event_count"};
  std::string header;
  for (const std::string& c : fixed_columns) {
    if (!header.empty()) header += ',';
    header += c;
  }
  for (const std::string& m : metric_names) {
    header += ',';
    header += csv_text(m);
  }
  out << header << kEol;

  for (const AttemptRecord& a : data.attempts) {
    std::vector<std::string> cells = {
        std::to_string(a.id),
        csv_text(a.uuid),
        csv_text(a.registration),
        csv_text(a.trainee_id.value_or("")),
        csv_text(a.module_id),
        attempt_status_name(a.status),
        csv_text(a.started_utc),
        csv_text(a.ended_utc.value_or("")),
        a.duration_s ? csv_number(*a.duration_s) : "",
        a.realtime_factor ? csv_number(*a.realtime_factor) : "",
        a.score ? csv_number(*a.score) : "",
        a.passed ? (*a.passed ? "true" : "false") : "",
        a.override_lock ? "true" : "false",
        csv_text(a.override_by),
        csv_text(a.override_reason),
        csv_text(a.input_device),
        csv_text(a.program_version),
        csv_text(a.scenario_hash),
        csv_text(a.abort_reason),
        std::to_string(a.events.size())};
    for (const std::string& name : metric_names) {
      const auto it = std::find_if(a.metrics.values.begin(), a.metrics.values.end(),
                                   [&](const auto& m) { return m.first == name; });
      cells.push_back(it == a.metrics.values.end() ? "" : csv_number(it->second));
    }
    std::string line;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (i > 0) line += ',';
      line += cells[i];
    }
    out << line << kEol;
  }
}

void write_report_json(const ReportData& data, std::ostream& out) {
  Json attempts = Json::array();
  for (const AttemptRecord& a : data.attempts) {
    Json metrics = Json::object();
    for (const auto& [name, value] : a.metrics.values) metrics[name] = value;
    Json terms = Json::array();
    for (const TermScore& t : a.score_detail.terms) {
      terms.push_back(Json{{"metric", t.metric}, {"value", t.value}, {"score", t.score}});
    }
    Json gates = Json::array();
    for (const GateResult& g : a.score_detail.gates) {
      gates.push_back(
          Json{{"metric", g.metric}, {"value", g.value}, {"max", g.max}, {"passed", g.passed}});
    }
    Json events = Json::array();
    for (const EventRecord& e : a.events) {
      events.push_back(Json{{"t_s", e.t_s},
                            {"kind", e.kind},
                            // null when the event is not about a zone, as stored
                            {"zone", e.zone.empty() ? Json(nullptr) : Json(e.zone)},
                            {"zone_index", e.zone_index >= 0 ? Json(e.zone_index) : Json(nullptr)},
                            {"value", e.value},
                            {"detail", e.detail}});
    }
    Json override_json = nullptr;
    if (a.override_lock) {
      override_json = Json{{"by", a.override_by}, {"reason", a.override_reason}};
    }
    attempts.push_back(Json{{"id", a.id},
                            {"uuid", a.uuid},
                            {"registration", a.registration},
                            {"trainee", optional_text(a.trainee_id)},
                            {"practice", a.is_practice()},
                            {"module", a.module_id},
                            {"status", attempt_status_name(a.status)},
                            {"started_utc", a.started_utc},
                            {"ended_utc", optional_text(a.ended_utc)},
                            {"duration_s", optional_number(a.duration_s)},
                            {"realtime_factor", optional_number(a.realtime_factor)},
                            {"score", optional_number(a.score)},
                            {"passed", a.passed ? Json(*a.passed) : Json(nullptr)},
                            {"override", override_json},
                            {"input_device", a.input_device},
                            {"program_version", a.program_version},
                            {"scenario_hash", a.scenario_hash},
                            {"abort_reason", a.abort_reason},
                            {"metrics", metrics},
                            {"score_terms", terms},
                            {"gates", gates},
                            {"reasons", a.score_detail.reasons},
                            {"events", events}});
  }
  Json progress = Json::array();
  for (const auto& [trainee, modules] : data.progress) {
    Json rows = Json::array();
    for (const ModuleProgress& p : modules) rows.push_back(progress_json(p));
    progress.push_back(Json{{"trainee", trainee}, {"modules", rows}});
  }
  const Json report{{"format", "acdr-report"},
                    {"version", 1},
                    {"filter", Json{{"trainee", optional_text(data.trainee_id)},
                                    {"module", optional_text(data.module_id)}}},
                    {"attempts", attempts},
                    {"progress", progress}};
  out << report.dump(2, ' ', false, Json::error_handler_t::replace) << '\n';
}

void write_report_xapi(const ReportData& data, const XapiOptions& options, std::ostream& out) {
  out << xapi_statements_json(data.attempts, data.modules, options) << '\n';
}

DbStatus write_report(Database& db, const ReportRequest& request, std::ostream& out) {
  DbResult<ReportData> data = collect_report(db, request);
  if (!data) return data.error();
  switch (request.format) {
    case ReportFormat::kTable: write_report_table(data.value(), out); break;
    case ReportFormat::kCsv: write_report_csv(data.value(), out); break;
    case ReportFormat::kJson: write_report_json(data.value(), out); break;
    case ReportFormat::kXapi: write_report_xapi(data.value(), request.xapi, out); break;
  }
  if (!out) return DbError{"report: writing the output failed", 0};
  return {};
}

}  // namespace acdr
