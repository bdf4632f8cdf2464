// `acdr report`: see report_command.hpp.
#include "cli/report_command.hpp"

#include <string>
#include <vector>

#include "db/attempt_store.hpp"
#include "db/catalog.hpp"
#include "db/database.hpp"
#include "db/report.hpp"
#include "net/lrs_config.hpp"

namespace acdr {

int run_report(const ReportOptions& options, std::ostream& out, std::ostream& err) {
  const std::optional<ReportFormat> format = parse_report_format(options.format);
  if (!format) {
    err << "acdr report: --format '" << options.format
        << "' is not known (expected table, csv, json or xapi)\n";
    return 2;
  }
  const std::string path = options.db_path.empty() ? default_database_path() : options.db_path;
  OpenOptions open_options;
  open_options.create = false;  // a report never starts an empty record
  std::vector<std::string> notes;  // results of earlier attempts stored from side files
  DbResult<Database> db = open_store(path, open_options, &notes);
  for (const std::string& line : notes) err << "note: " << line << '\n';
  if (!db) {
    err << "acdr report: " << db.error().message << '\n';
    return 2;  // missing, empty or another program's file: refused, as rescore and dashboard do
  }
  // A trainee or module the record does not know is a mistake (a typo, the wrong record), not
  // an empty report: say so, with what the record does hold.
  if (options.trainee) {
    DbResult<std::optional<TraineeRecord>> known = find_trainee(db.value(), *options.trainee);
    if (!known) {
      err << "acdr report: " << known.error().message << '\n';
      return 1;
    }
    if (!known.value()) {
      DbResult<std::vector<TraineeRecord>> all = list_trainees(db.value());
      std::string ids;
      if (all)
        for (const TraineeRecord& t : all.value()) ids += (ids.empty() ? "" : ", ") + t.id;
      err << "acdr report: no trainee '" << *options.trainee << "' in " << path << " ("
          << (ids.empty() ? std::string("it has no trainees yet") : "trainees: " + ids) << ")\n";
      return 2;
    }
  }
  if (options.module) {
    DbResult<std::optional<ModuleRecord>> known = find_module(db.value(), *options.module);
    if (!known) {
      err << "acdr report: " << known.error().message << '\n';
      return 1;
    }
    if (!known.value()) {
      DbResult<std::vector<ModuleRecord>> all = list_modules(db.value());
      std::string ids;
      if (all)
        for (const ModuleRecord& m : all.value()) ids += (ids.empty() ? "" : ", ") + m.id;
      err << "acdr report: no module '" << *options.module << "' in " << path << " ("
          << (ids.empty() ? std::string("it has no modules yet") : "modules: " + ids) << ")\n";
      return 2;
    }
  }
  ReportRequest request;
  request.trainee_id = options.trainee;
  request.module_id = options.module;
  request.format = *format;
  request.include_practice = options.include_practice;
  if (!options.xapi_base_iri.empty()) {
    request.xapi.base_iri = options.xapi_base_iri;
  } else if (*format == ReportFormat::kXapi) {
    // The same IRI base as the statements queued for the record store.
    const LrsConfigLoad lrs = load_lrs_config(options.lrs_config);
    if (!lrs.ok()) {
      err << "acdr report: " << lrs.error << '\n';
      return 2;
    }
    if (!lrs.config.activity_iri_base.empty()) {
      request.xapi.base_iri = lrs.config.activity_iri_base;
    }
  }
  if (!options.xapi_account_home_page.empty()) {
    request.xapi.account_home_page = options.xapi_account_home_page;
  }
  if (DbStatus s = write_report(db.value(), request, out); !s) {
    err << "acdr report: " << s.error().message << '\n';
    return 1;
  }
  return 0;
}

}  // namespace acdr
