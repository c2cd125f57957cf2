#pragma once
/// @file stop_signals.hpp
/// Ctrl-C for a long run of a command-line program: while a StopSignals lives, SIGINT and
/// SIGTERM raise a process-wide flag that a RunControl's `stop` points at (the run finishes its
/// current step, writes nothing and returns its interrupted status); a second signal ends the
/// process at once (outputs are written by rename, so no file is left half-written). The
/// previous handlers come back when it is destroyed. Python front ends use their own
/// (KeyboardInterrupt); this is for programs that own the process's signals.

#include <atomic>

namespace taskmap {

/// Installs the handlers for its lifetime (one at a time per process: nested instances throw
/// Error). The flag starts false.
class StopSignals {
 public:
  /// Installs SIGINT and SIGTERM handlers that raise flag(); throws Error when another
  /// StopSignals is alive.
  StopSignals();
  /// Restores the handlers that were installed before.
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  /// The flag to pass as RunControl::stop (or ValidateControl::stop); true after a signal.
  static const std::atomic<bool>* flag();
};

}  // namespace taskmap
