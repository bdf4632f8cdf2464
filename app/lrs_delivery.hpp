// Sending the training record's outbox (db/outbox.hpp) to the configured learning record store
// (net/lrs_client.hpp): the statements go one by one in queue order, each marked in the record
// as soon as the store has answered for it, so a run stopped at any point (the program killed,
// the network gone) loses nothing and repeats at most the one statement in flight, which the
// store recognises by its id.
//
// When the store cannot be reached or is busy, the same statement is tried again after a
// pause that doubles each time (first_backoff_s, 2x, ... up to max_backoff_s), for at most
// retry_for_s; then sending stops and the statements stay queued for the next run. A statement
// the store refuses for good (a 4xx other than those below) is marked failed with the store's
// message and the others go on. Refused credentials or a wrong endpoint stop sending at once
// and leave every statement queued.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "db/database.hpp"
#include "db/outbox.hpp"
#include "net/lrs_config.hpp"

namespace acdr {

struct DeliveryOptions {
  double retry_for_s = 60.0;  ///< how long to keep trying while the store is unreachable
  double first_backoff_s = 0.5;
  double max_backoff_s = 30.0;
  std::int64_t max_statements = -1;  ///< stop after this many answered statements (< 0: all)
};

struct DeliveryReport {
  std::string endpoint;             ///< where they went (no credentials)
  std::int64_t stored = 0;          ///< taken by the store now
  std::int64_t already_stored = 0;  ///< the store had them (sent before an interruption)
  std::int64_t rejected = 0;        ///< marked failed
  std::int64_t failed_tries = 0;    ///< tries that found the store unreachable or busy
  OutboxCounts left;                ///< the outbox afterwards
  /// Why sending stopped before the queue was empty ("" when it emptied it): the store's or the
  /// network's last answer.
  std::string stopped;
  bool config_problem = false;  ///< stopped because credentials or endpoint are wrong
  /// "statement-id: message" of each statement marked failed in this run.
  std::vector<std::string> rejections;
  /// A problem with the training record itself (the run stopped); "" otherwise.
  std::string record_error;

  bool emptied() const { return stopped.empty() && record_error.empty(); }
};

/// Sends the queued statements of `db` to `config`'s store as described above. `config` must
/// have an endpoint.
DeliveryReport deliver_outbox(Database& db, const LrsConfig& config,
                              const DeliveryOptions& options = {});

}  // namespace acdr
