#pragma once
/// @file build_report.hpp
/// What a build and a data set report, as text: the progress line (a bar on a terminal, a log
/// line otherwise), the summary of a written map, the physics validation's line and a finished
/// data-set job's line. `taskmap build`, `taskmap dataset` and `taskmap-mpi` print these; a C++
/// or Python caller can print the same.

#include <cstddef>
#include <optional>
#include <string>

#include "taskmap/builder/dataset.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/builder/map_file_build.hpp"

namespace taskmap {

/// "hh:mm:ss" of a duration in seconds (rounded), "--:--:--" when negative, not finite or
/// beyond 99:59:59.
std::string clockString(double seconds);

/// The share of a build's trials and targets done, in [0, 1]: the larger of valid grasps found
/// over the target and trials over the budget.
double buildProgressFraction(const BuildProgress& p);

/// One progress report as text. Bar style: "\r[####----]  40%  blocks ...  trials N  valid V/T
/// R trials/s  ETA hh:mm:ss " (no newline, redraws in place). Log style: "<label>: hh:mm:ss
/// elapsed, ... ETA hh:mm:ss\n".
std::string buildProgressLine(const BuildProgress& p, const std::string& label, bool bar);

/// The summary of a built map (status line, object and hand, trial outcomes, stored grasps and
/// clusters, time per phase and the CPU shares of sampling, simulation and quality, the closing
/// check's cost when it ran, the output path); one line per item, each ending in '\n'.
/// @param threads_note text after "threads", e.g. "2 (not stored: ...)".
/// @param write_seconds time spent writing the file, s (added to the wall time).
std::string buildSummaryText(const std::string& label, const BuildResult& result,
                             double write_seconds, const std::string& threads_note,
                             const std::string& output);

/// The warning a build whose trial budget ran out gets ("<label>: warning: ...; raise --trials
/// or check the object and hand\n"), or "" for any other status.
std::string buildBudgetWarning(const std::string& label, const BuildResult& result);

/// "<label>: physics validation: H of T grasps hold (P %), R grasps per CPU-second\n", plus
/// the --keep-holding line when keep_holding; "" without labels.
std::string holdLabelsText(const std::string& label, const std::optional<HoldLabels>& labels,
                           bool keep_holding);

/// One line for a finished data-set job: "[done/total, ETA hh:mm:ss] object x hand: status, V
/// valid in T trials -> file" (or the error); no newline. @param elapsed_seconds since the
/// first job started.
std::string datasetProgressLine(std::size_t done, std::size_t total, double elapsed_seconds,
                                const DatasetEntry& entry);

}  // namespace taskmap
