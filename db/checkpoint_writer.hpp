// Checkpoints of a running attempt made from its record: what was recorded since the previous
// checkpoint becomes the next recording piece (the header first), with the new events and the
// metrics of the record so far, appended by append_checkpoint (attempt_store.hpp). The one way
// checkpoints are made, whoever drives the attempt: a headless replay calls it on its stepping
// thread, a live attempt on its writer thread (app/live_attempt_checkpoints.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <span>
#include <vector>

#include "assessment/attempt_recording.hpp"
#include "db/database.hpp"
#include "db/records.hpp"

namespace acdr {

/// The engine's events as the record stores them: a zone event keeps its zone's index and,
/// from `zones`, its name.
std::vector<EventRecord> event_records(std::span<const Event> events,
                                       const std::vector<WorldSummary::Zone>& zones);

class CheckpointWriter {
 public:
  /// `db` and `err` must outlive the writer; while it writes, no other thread may use `db` (a
  /// live attempt gives its writer thread a connection of its own). The attempt must be running.
  CheckpointWriter(Database& db, std::int64_t attempt_id, std::ostream& err);

  /// Appends the part of `record` from `first_new_frame`, `first_new_event` and
  /// `first_new_bone_sample` on as the next checkpoint (the bone's load samples too, so an
  /// attempt that never finishes keeps its stress history for a re-score), with the metrics of
  /// the whole `record` and the simulated time so far `t_s` (s). Returns whether it was saved;
  /// when not (the store refused: warned on `err` once), the caller passes the same first
  /// indices again next time, so nothing is lost.
  bool write(const AttemptRecording& record, std::size_t first_new_frame,
             std::size_t first_new_event, std::size_t first_new_bone_sample, double t_s);

  int saved() const { return saved_; }

 private:
  Database& db_;
  std::int64_t attempt_id_;
  std::ostream& err_;
  bool header_saved_ = false;
  bool warned_ = false;
  int saved_ = 0;
};

}  // namespace acdr
