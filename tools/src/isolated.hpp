#pragma once
/// @file isolated.hpp
/// Running work that parses an unverified file (HDF5 may crash or hang on a damaged one) in a
/// child process with CPU-time and address-space limits, so that the tool reports a refusal
/// instead of crashing or hanging.

#include <functional>
#include <string>

namespace taskmap::cli {

/// Limits of the child process.
struct IsolationLimits {
  int cpu_seconds = 120;    ///< RLIMIT_CPU, seconds
  double memory_gib = 8.0;  ///< RLIMIT_AS, GiB
};

/// Runs body in a forked child with the limits; the child's stdout and stderr are the tool's.
/// An exception thrown by body comes back as Error with the same message; a child killed by a
/// signal (crash, CPU limit) or out of memory becomes Error("<what>: <reason>"). Call only
/// from the single-threaded tool (fork).
void runIsolated(const std::function<void()>& body, const IsolationLimits& limits,
                 const std::string& what);

}  // namespace taskmap::cli
