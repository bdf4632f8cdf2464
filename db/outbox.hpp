// The outbox of xAPI statements in the training record: store first, send after.
//
// Finishing a completed trainee attempt queues its statements (the ones `acdr report --format
// xapi` exports for it) in the same transaction as the attempt itself, so a stored attempt
// always has its statements waiting, whatever happens to the network afterwards. A sender
// (app/lrs_delivery.hpp) takes the queued statements in queue order and marks each one sent,
// or failed when the learning record store refused it for good, or notes a failed try and
// leaves it queued. The statement id is the key: queueing the same statement twice is a no-op,
// and the store treats a repeated id as the same statement.
//
// The statement text is frozen when queued (xAPI statements are immutable): re-scoring an
// attempt later changes its export, not what is queued or sent. No credentials are kept here.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "db/database.hpp"
#include "db/xapi.hpp"

namespace acdr {

enum class OutboxState {
  kQueued,  ///< waiting to be sent (again)
  kSent,    ///< the record store has it (stored now, or had it already)
  kFailed,  ///< refused by the record store for good; kept with its answer, not retried
};

/// "queued", "sent", "failed".
const char* outbox_state_name(OutboxState state);

/// One statement in the outbox.
struct OutboxItem {
  std::int64_t id = 0;  ///< queue order
  std::string statement_id;
  std::int64_t attempt_id = 0;
  std::string statement;  ///< the JSON text to send
  std::string queued_utc;
  OutboxState state = OutboxState::kQueued;
  int tries = 0;  ///< sending tries that did not end in sent/failed, plus the last one
  std::optional<std::string> last_try_utc;
  std::string last_error;  ///< the last problem (transport error or the store's answer)
  std::optional<std::string> sent_utc;
  std::string sent_to;  ///< the endpoint that took it (no credentials)
};

struct OutboxCounts {
  std::int64_t queued = 0;
  std::int64_t sent = 0;
  std::int64_t failed = 0;
};

/// Queues the statements of one attempt (none for a practice, running or aborted attempt).
/// Runs in the caller's transaction when there is one (finish_attempt calls it inside its
/// own), else in a transaction of its own. Statements already in the outbox are left as they
/// are. Returns how many were newly queued.
DbResult<int> queue_attempt_statements(Database& db, std::int64_t attempt_id,
                                       const XapiOptions& options);

/// Queues the statements of every completed trainee attempt that are not in the outbox yet
/// (records from before the outbox, or statements lost by a deleted outbox row), in start
/// order, in one transaction. Returns how many were newly queued.
DbResult<int> queue_all_statements(Database& db, const XapiOptions& options);

/// Up to `limit` queued statements, in queue order.
DbResult<std::vector<OutboxItem>> queued_statements(Database& db, int limit);

/// Every statement of the outbox in queue order, or only those in `state`.
DbResult<std::vector<OutboxItem>> list_outbox(Database& db,
                                              std::optional<OutboxState> state = std::nullopt);

/// The record store has statement `id` (its answer in `note`, e.g. that it was stored
/// already): state sent, sent_utc now, sent_to `endpoint`. Counts the try.
DbStatus mark_statement_sent(Database& db, std::int64_t id, const std::string& endpoint,
                             const std::string& note = "");

/// The record store refused statement `id` for good: state failed, `error` kept. Counts the
/// try.
DbStatus mark_statement_failed(Database& db, std::int64_t id, const std::string& error);

/// A try that may succeed later (network down, store busy): counted, `error` kept, still
/// queued.
DbStatus note_statement_try(Database& db, std::int64_t id, const std::string& error);

/// Puts failed statements back in the queue (after the cause was fixed); returns how many.
DbResult<int> requeue_failed_statements(Database& db);

DbResult<OutboxCounts> outbox_counts(Database& db);

}  // namespace acdr
