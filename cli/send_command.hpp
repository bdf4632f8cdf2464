// `acdr send`: sends the training record's outbox of xAPI statements to the configured
// learning record store (app/lrs_delivery.hpp) and says what it sent. The CLI parses the flags
// into SendOptions and calls run_send.
#pragma once

#include <iostream>
#include <optional>
#include <ostream>
#include <string>

#include "app/lrs_delivery.hpp"

namespace acdr {

struct SendOptions {
  std::string db_path;                ///< empty: default_database_path() ($ACDR_DB, XDG)
  std::optional<std::string> config;  ///< --config FILE (else $ACDR_LRS_CONFIG, XDG, env)
  double retry_for_s = 60.0;          ///< --retry-for: keep trying an unreachable store
  bool queue_existing = false;        ///< --queue-existing: queue attempts stored before the outbox
  bool retry_failed = false;          ///< --retry-failed: queue refused statements again first
};

/// One line (or a few) saying what a delivery did: counts, why it stopped, each refusal.
std::string delivery_summary(const DeliveryReport& report);

/// Exit codes: 0 the outbox is sent (nothing queued is left, nothing refused in this run);
/// 1 the record or the configuration is wrong (no endpoint, refused credentials, wrong
/// endpoint; nothing was marked sent that the store did not take); 2 bad options; 3 the store
/// could not be reached in time (the rest stays queued: run it again); 4 the store refused some
/// statements for good (marked failed with its message; --retry-failed after fixing the cause).
int run_send(const SendOptions& options, std::ostream& out, std::ostream& err = std::cerr);

}  // namespace acdr
