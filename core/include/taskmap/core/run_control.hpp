#pragma once
/// @file run_control.hpp
/// How a caller watches and stops a long run (a map build, a data set, a reach plan): one
/// struct, the same for every stage. A stage that reports its own bookkeeping through the
/// callback chains the caller's (chained()), never replaces it.

#include <atomic>
#include <functional>
#include <string>
#include <utility>

#include "taskmap/core/error.hpp"

namespace taskmap {

/// Progress reports, interval and stop flag of a run. `Progress` is the stage's report type
/// (BuildProgress, DatasetProgress, PlanProgress).
template <class Progress>
struct RunControl {
  /// Receives a report on the thread that started the run, about every interval_seconds (or at
  /// the steps the stage names). May throw: the run stops (its workers joined, nothing written)
  /// and the exception leaves the run's call.
  std::function<void(const Progress&)> progress;
  double interval_seconds = 0.25;  ///< seconds between reports, > 0
  /// When it becomes true the run stops soon (workers finish their current step) and returns
  /// its interrupted status; nullptr: never stopped. Read from several threads.
  const std::atomic<bool>* stop = nullptr;

  /// True when stop is set and raised.
  bool stopRequested() const { return stop != nullptr && stop->load(); }

  /// Throws Error naming the field when interval_seconds is not positive.
  void validate() const {
    if (!(interval_seconds > 0.0))
      throw Error("run control: interval_seconds must be positive (got " +
                  std::to_string(interval_seconds) + ")");
  }

  /// This control with `first` called before the caller's progress callback (a stage's own
  /// bookkeeping, chained instead of replacing the caller's).
  RunControl chained(std::function<void(const Progress&)> first) const {
    RunControl c = *this;
    c.progress = [first = std::move(first), then = progress](const Progress& p) {
      if (first) first(p);
      if (then) then(p);
    };
    return c;
  }
};

}  // namespace taskmap
