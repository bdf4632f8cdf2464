// Sending the outbox to the learning record store: see lrs_delivery.hpp.
#include "app/lrs_delivery.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

#include "net/lrs_client.hpp"

namespace acdr {

namespace {

using Clock = std::chrono::steady_clock;

// Records what the store said about one statement. Returns false when the record refused.
bool record_reply(Database& db, const OutboxItem& item, const LrsReply& reply,
                  const std::string& endpoint, DeliveryReport& report) {
  DbStatus status;
  switch (reply.answer) {
    case LrsAnswer::kStored:
      status = mark_statement_sent(db, item.id, endpoint);
      ++report.stored;
      break;
    case LrsAnswer::kAlreadyStored:
      status = mark_statement_sent(db, item.id, endpoint, reply.message);
      ++report.already_stored;
      break;
    case LrsAnswer::kRejected:
      status = mark_statement_failed(db, item.id, reply.message);
      ++report.rejected;
      report.rejections.push_back(item.statement_id + ": " + reply.message);
      break;
    case LrsAnswer::kTryLater:
    case LrsAnswer::kConfigProblem:
      status = note_statement_try(db, item.id, reply.message);
      break;
  }
  if (!status) {
    report.record_error = status.error().message;
    return false;
  }
  return true;
}

}  // namespace

DeliveryReport deliver_outbox(Database& db, const LrsConfig& config,
                              const DeliveryOptions& options) {
  DeliveryReport report;
  report.endpoint = config.endpoint;
  if (!config.has_endpoint()) {
    report.stopped = "no LRS endpoint is configured";
    report.config_problem = true;
  }
  LrsClient client(config);
  std::int64_t answered = 0;
  constexpr int kBatch = 64;
  while (report.stopped.empty() && report.record_error.empty()) {
    DbResult<std::vector<OutboxItem>> batch = queued_statements(db, kBatch);
    if (!batch) {
      report.record_error = batch.error().message;
      break;
    }
    if (batch->empty()) break;
    for (const OutboxItem& item : batch.value()) {
      if (options.max_statements >= 0 && answered >= options.max_statements) {
        report.stopped = "stopped after " + std::to_string(answered) + " statements as asked";
        break;
      }
      // Try this statement until the store answers for it, backing off while it cannot.
      double backoff = options.first_backoff_s;
      const Clock::time_point first_failure = Clock::now();
      LrsReply reply;
      while (true) {
        reply = client.put_statement(item.statement_id, item.statement);
        if (!record_reply(db, item, reply, config.endpoint, report)) break;
        if (reply.answer != LrsAnswer::kTryLater) break;
        ++report.failed_tries;
        const double waited = std::chrono::duration<double>(Clock::now() - first_failure).count();
        if (waited + backoff > options.retry_for_s) break;
        std::this_thread::sleep_for(std::chrono::duration<double>(backoff));
        backoff = std::min(backoff * 2.0, options.max_backoff_s);
      }
      if (!report.record_error.empty()) break;
      if (reply.answer == LrsAnswer::kTryLater) {
        report.stopped = reply.message;
        break;
      }
      if (reply.answer == LrsAnswer::kConfigProblem) {
        report.stopped = reply.message;
        report.config_problem = true;
        break;
      }
      ++answered;
    }
  }
  if (DbResult<OutboxCounts> counts = outbox_counts(db); counts) {
    report.left = counts.value();
  } else if (report.record_error.empty()) {
    report.record_error = counts.error().message;
  }
  return report;
}

}  // namespace acdr
