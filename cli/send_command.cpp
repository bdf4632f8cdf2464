// `acdr send`: see send_command.hpp.
#include "cli/send_command.hpp"

#include "db/attempt_store.hpp"
#include "db/database.hpp"
#include "db/outbox.hpp"
#include "net/lrs_config.hpp"

namespace acdr {

std::string delivery_summary(const DeliveryReport& report) {
  std::string s = "sent to " + report.endpoint + "statements: " + std::to_string(report.stored) +
                  " stored, " + std::to_string(report.already_stored) + " already stored, " +
                  std::to_string(report.rejected) + " refused";
  if (report.failed_tries > 0) {
    s += " (" + std::to_string(report.failed_tries) + " tries found the store unreachable)";
  }
  s += "; outbox now " + std::to_string(report.left.queued) + " queued, " +
       std::to_string(report.left.sent) + " sent, " + std::to_string(report.left.failed) +
       " failed\n";
  for (const std::string& r : report.rejections) s += "  refused " + r + "\n";
  if (!report.record_error.empty()) s += "  stopped: " + report.record_error + "\n";
  if (!report.stopped.empty()) {
    s += "  stopped: " + report.stopped;
    s += report.config_problem ? "\n" : " (the rest stays queued: run acdr send again)\n";
  }
  return s;
}

int run_send(const SendOptions& options, std::ostream& out, std::ostream& err) {
  if (!(options.retry_for_s >= 0.0)) {
    err << "acdr send: --retry-for must be a number of seconds >= 0\n";
    return 2;
  }
  const LrsConfigLoad lrs = load_lrs_config(options.config);
  if (!lrs.ok()) {
    err << "acdr send: " << lrs.error << '\n';
    return 1;
  }
  const std::string path = options.db_path.empty() ? default_database_path() : options.db_path;
  OpenOptions open_options;
  open_options.create = false;  // sending never starts an empty record
  DbResult<Database> db = open_store(path, open_options);
  if (!db) {
    err << "acdr send: " << db.error().message << '\n';
    return 1;
  }
  if (options.queue_existing) {
    XapiOptions xapi;
    if (!lrs.config.activity_iri_base.empty()) xapi.base_iri = lrs.config.activity_iri_base;
    DbResult<int> added = queue_all_statements(db.value(), xapi);
    if (!added) {
      err << "acdr send: " << added.error().message << '\n';
      return 1;
    }
    out << "queued " << added.value() << " statements of attempts not in the outbox yet\n";
  }
  if (options.retry_failed) {
    DbResult<int> again = requeue_failed_statements(db.value());
    if (!again) {
      err << "acdr send: " << again.error().message << '\n';
      return 1;
    }
    out << "queued " << again.value() << " refused statements again\n";
  }
  if (!lrs.config.has_endpoint()) {
    err << "acdr send: no LRS endpoint is configured (set \"endpoint\" in "
        << (options.config ? *options.config : default_lrs_config_path())
        << " or ACDR_LRS_ENDPOINT); the statements stay queued\n";
    return 1;
  }
  DeliveryOptions delivery;
  delivery.retry_for_s = options.retry_for_s;
  const DeliveryReport report = deliver_outbox(db.value(), lrs.config, delivery);
  const std::string summary = delivery_summary(report);
  if (!report.record_error.empty() || report.config_problem) {
    err << "acdr send: " << summary;
    return 1;
  }
  out << summary;
  if (!report.stopped.empty()) return 3;
  if (report.rejected > 0) return 4;
  return 0;
}

}  // namespace acdr
