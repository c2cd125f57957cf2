#pragma once
/// @file regression_suite.hpp
/// The regression suite on reference objects (tests/regression/, `taskmap regress`): each case
/// builds a small map with a fixed seed and trial budget, reduces it to statistics
/// (inspect/regression.hpp) and compares them with the checked-in golden file, or rewrites it.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "taskmap/inspect/regression.hpp"

namespace taskmap {

/// Which cases to run, against which golden files.
struct RegressionSuiteOptions {
  std::string cases;               ///< case list (JSON); "": <data dir>/regression/cases.json
  std::string golden_dir;          ///< golden files; "": <folder of the case list>/golden
  std::vector<std::string> only;   ///< run only these cases (by name); empty: all
  bool update = false;             ///< rewrite the golden files instead of comparing
  int threads = 0;                 ///< worker threads (0: all cores); results do not depend on it
  std::optional<double> friction;  ///< override the quality's friction (to see the suite catch it)
};

/// One case as run.
struct RegressionCaseRun {
  /// kCompared: compared with its golden file; kUpdated: golden file rewritten; kNoGolden: no
  /// golden file to compare with (counted as a failure).
  enum class Outcome { kCompared, kUpdated, kNoGolden };
  RegressionCase spec;                   ///< the case as listed
  std::string object, hand;              ///< names of the loaded object and hand
  double wall_seconds = 0.0;             ///< time of its build, s
  std::string golden_path;               ///< its golden file
  Outcome outcome = Outcome::kCompared;  ///< see Outcome
  RegressionResult comparison;           ///< the rows (kCompared only)
  int failures = 0;                      ///< failed statistics (1 for kNoGolden)
};

/// The whole run.
struct RegressionSuiteResult {
  std::vector<RegressionCaseRun> cases;  ///< in the order of the list
  int failures = 0;                      ///< failed statistics of all cases
  std::string cases_path, golden_dir;    ///< as resolved (absolute)
};

/// Runs the cases of options (each after the previous; on_case, if given, sees each as it
/// finishes). Throws Error naming the file for a bad case list, a missing mesh or hand, or
/// when no case matches `only`.
RegressionSuiteResult runRegressionSuite(
    const RegressionSuiteOptions& options,
    const std::function<void(const RegressionCaseRun&)>& on_case = {});

/// A case as `taskmap regress` prints it: "== name: object with hand, T trials, seed S, sampler
/// K (W s)", then the table of statistics (golden, now, verdict) or the update / missing-golden
/// line; lines end in '\n'.
std::string regressionCaseText(const RegressionCaseRun& run);

}  // namespace taskmap
