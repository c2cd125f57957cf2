#pragma once
/// @file run_lock.hpp
/// One run at a time on a data-set directory or a build output: an exclusive flock on a lock
/// file that records the holder's PID. A second run refuses at once, naming the holder; the lock
/// goes with the process (a killed run leaves a stale file, not a held lock).

#include <string>

namespace taskmap {

class RunLock {
 public:
  /// Takes the lock on lock_path (created if missing). Throws Error("<what> is in use by
  /// another taskmap run (PID n, lock file ...); wait for it to finish") when another process
  /// holds it, or Error naming the file when it cannot be created.
  RunLock(std::string lock_path, const std::string& what);
  ~RunLock();
  RunLock(const RunLock&) = delete;
  RunLock& operator=(const RunLock&) = delete;

 private:
  bool tryLock(const std::string& what);
  std::string path_;
  int fd_ = -1;
};

}  // namespace taskmap
