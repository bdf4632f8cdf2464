// Who is writing a running attempt, and whether that process still exists. Used to tell an
// attempt whose program was killed from one that is still being recorded.
#pragma once

#include <cstdint>
#include <string>

namespace acdr {

/// The identity of a process on a machine since its last boot.
struct WriterIdentity {
  std::int64_t pid = 0;
  /// Process start time in clock ticks since boot (/proc/<pid>/stat field 22); tells a live
  /// writer from an unrelated process that later got the same pid. 0 when unknown.
  std::int64_t start_ticks = 0;
  /// "<hostname>/<boot id>": a different value means another machine or another boot.
  std::string host;
};

/// The calling process.
WriterIdentity current_writer();

enum class WriterState {
  kAlive,  ///< the same process is still running on this machine
  kGone,   ///< exited, killed, a zombie, or the pid now belongs to another process
};

/// Decides whether `writer` can still be writing. The rule:
/// - another host or another boot -> gone (a WAL database is only shared through memory on one
///   machine, so a writer elsewhere cannot be writing to this file);
/// - same host: no process with that pid, or a zombie -> gone;
/// - the pid exists but started at another time -> gone (pid reused);
/// - otherwise alive.
WriterState writer_state(const WriterIdentity& writer);

}  // namespace acdr
