#pragma once
// The Python side of a long run (a build, a data set, a validation): the user's progress
// callback, the stop flag the run polls, and the first Python error (KeyboardInterrupt from a
// signal, or the callback's exception) kept until the GIL is back. The run itself goes with
// the GIL released; report() takes it back on the calling thread.

#include <pybind11/pybind11.h>

#include <atomic>
#include <optional>
#include <type_traits>
#include <utility>

namespace taskmap {

/// A run's Python callback, stop flag and pending Python error.
class PythonRun {
 public:
  /// @param callback called with each report (None: signals are still checked).
  explicit PythonRun(pybind11::object callback) : callback_(std::move(callback)) {}
  ~PythonRun() {
    if (!error_) return;
    pybind11::gil_scoped_acquire acquire;
    error_.reset();
  }
  PythonRun(const PythonRun&) = delete;
  PythonRun& operator=(const PythonRun&) = delete;

  /// The flag the run polls: raised by Ctrl-C or by an exception of the callback.
  const std::atomic<bool>* stop() const { return &stop_; }

  /// Called with the GIL released: takes it, checks signals and, with a report maker (not
  /// nullptr), calls back with its report.
  template <class MakeReport>
  void report(MakeReport&& make) {
    if (stop_.load()) return;
    pybind11::gil_scoped_acquire acquire;
    try {
      if (PyErr_CheckSignals() != 0) throw pybind11::error_already_set();
      if constexpr (!std::is_same_v<std::decay_t<MakeReport>, std::nullptr_t>)
        if (!callback_.is_none()) callback_(make());
    } catch (pybind11::error_already_set& e) {
      error_.emplace(std::move(e));
      stop_.store(true);
    }
  }

  /// With the GIL held: raises the kept error, if any.
  void raiseIfFailed() {
    if (!error_) return;
    pybind11::error_already_set e = std::move(*error_);
    error_.reset();
    throw e;
  }

 private:
  pybind11::object callback_;
  std::atomic<bool> stop_{false};
  std::optional<pybind11::error_already_set> error_;
};

}  // namespace taskmap
