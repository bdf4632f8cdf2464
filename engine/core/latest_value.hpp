// Hands the newest value of something from a real-time thread (the haptic loop) to a reader
// (the renderer, a status display) without ever making the real-time thread wait: the writer
// only try-locks and skips publishing when the reader happens to hold the lock; the reader
// holds the lock only to copy the value out.
#pragma once

#include <cstdint>
#include <mutex>

namespace acdr {

template <class T>
class LatestValue {
 public:
  /// Writer side: if the lock is free right now, calls fill(T&) on the shared value and
  /// returns true; otherwise returns false at once (try again on a later step).
  template <class Fill>
  bool try_publish(Fill&& fill) {
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return false;
    fill(value_);
    ++version_;
    return true;
  }

  /// Writer side, when waiting is acceptable (e.g. after the last step).
  template <class Fill>
  void publish(Fill&& fill) {
    std::lock_guard lock(mutex_);
    fill(value_);
    ++version_;
  }

  /// Reader side: calls read(const T&) under the lock when the value is newer than
  /// `*seen_version` (or always when seen_version is null); returns whether it read. Copy
  /// inside `read` and work on the copy afterwards.
  template <class Read>
  bool read(Read&& read, std::uint64_t* seen_version = nullptr) const {
    std::lock_guard lock(mutex_);
    if (seen_version && *seen_version == version_) return false;
    read(value_);
    if (seen_version) *seen_version = version_;
    return true;
  }

  /// Number of publications so far.
  std::uint64_t version() const {
    std::lock_guard lock(mutex_);
    return version_;
  }

 private:
  mutable std::mutex mutex_;
  T value_{};
  std::uint64_t version_ = 0;
};

}  // namespace acdr
