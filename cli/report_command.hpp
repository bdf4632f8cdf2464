// `acdr report`: attempts and progress from the training record, as a table, CSV, JSON or xAPI
// statements. The CLI parses the flags into ReportOptions and calls run_report.
#pragma once

#include <iostream>
#include <optional>
#include <ostream>
#include <string>

namespace acdr {

struct ReportOptions {
  std::string db_path;                 ///< empty: default_database_path() ($ACDR_DB, XDG)
  std::optional<std::string> trainee;  ///< --trainee ID
  std::optional<std::string> module;   ///< --module ID
  std::string format = "table";        ///< --format table|csv|json|xapi
  bool include_practice = true;        ///< practice attempts in table/csv/json
  std::string xapi_base_iri;           ///< empty: XapiOptions' default
  std::string xapi_account_home_page;  ///< empty: XapiOptions' default
  /// xapi: the LRS configuration file whose activity_iri_base is used when xapi_base_iri is
  /// empty (else $ACDR_LRS_CONFIG, the XDG default, ACDR_XAPI_IRI_BASE; net/lrs_config.hpp).
  std::optional<std::string> lrs_config;
};

/// Writes the report to `out`; problems go to `err` as one line each. Returns the process exit
/// code: 0 on success, 2 for bad options (unknown format; a --trainee or --module the record
/// does not hold, with the ids it does hold), 1 when the record cannot be read
/// (no file, newer schema, ...). Never creates a database: a mistyped --db is reported. Opening
/// marks attempts left running by killed programs as aborted, so they show as such.
int run_report(const ReportOptions& options, std::ostream& out, std::ostream& err = std::cerr);

}  // namespace acdr
