// Lowers the calling thread's scheduling priority, for helper threads of a live attempt (the
// checkpoint writer, the bone's solver) that must never take a core from the device and
// physics loops.
#pragma once

namespace acdr {

/// SCHED_BATCH (on Linux a waking batch thread never preempts a running one) and nice 10 (about
/// a tenth of a core's share when the cores are contended). Both are allowed without
/// privileges. Returns whether both were applied.
bool lower_this_threads_priority();

}  // namespace acdr
