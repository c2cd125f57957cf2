#pragma once
/// @file regression.hpp
/// Regression suite on reference objects: build a small map per (object, hand) case with a
/// fixed seed and trial budget, reduce it to golden statistics, compare with checked-in ones.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap {

/// One case of the suite (an entry of tests/regression/cases.json).
struct RegressionCase {
  std::string name;     ///< also the golden file's stem
  std::string object;   ///< mesh path, relative to the suite's root directory
  std::string hand;     ///< URDF path, relative to the suite's root directory
  std::string sidecar;  ///< hand sidecar relative to the root; empty: the URDF's <stem>.hand.json
  std::string sampler;  ///< "volume", "surface" or "mixed"
  std::uint64_t seed = 1;
  std::uint64_t trials = 1000;  ///< fixed trial budget (every trial runs)
};

/// Statistics that say what a map says; what the golden files hold.
struct MapStatistics {
  std::uint64_t trials = 0;                                        ///< trials simulated
  std::map<std::string, std::uint64_t> outcomes;                   ///< trials per outcome status
  std::uint64_t valid = 0;                                         ///< force-closure grasps
  double valid_rate = 0.0;                                         ///< valid / trials
  double epsilon_q10 = 0.0, epsilon_q50 = 0.0, epsilon_q90 = 0.0;  ///< of valid grasps
  std::vector<int> cluster_sizes;                                  ///< largest first
  int outliers = 0;                                                ///< grasps labelled -1
  std::vector<std::vector<double>> representatives;  ///< per cluster: x y z qw qx qy qz
};

/// One compared statistic.
struct ComparisonRow {
  std::string case_name;  ///< the case (RegressionCase::name)
  std::string statistic;  ///< e.g. "valid rate", "cluster 0 representative"
  std::string golden;     ///< the golden value as printed
  std::string now;        ///< this build's value as printed
  bool pass = true;       ///< within the suite's tolerance
};

/// Reduces a map to its statistics (quantiles: linear interpolation, numpy's default).
MapStatistics computeStatistics(const TaskMapData& map);
/// The golden file of case c: the statistics (keys trials, outcomes, valid, valid_rate,
/// epsilon_quantiles {q10, q50, q90}, clusters, cluster_sizes, outliers, representatives) and
/// "case" (object, hand, [sidecar,] sampler, seed, trials), JSON indented by 2, newline-ended.
std::string goldenFileText(const MapStatistics& s, const RegressionCase& c);

/// Statistics read from a golden file; nullopt when the file cannot be opened. Throws Error
/// naming the file when it is not valid JSON or lacks a statistic.
std::optional<MapStatistics> readGoldenFile(const std::string& path);

/// Statistics parsed from golden JSON text; `source` names it in the Error thrown when the
/// text is not valid JSON or lacks a statistic.
MapStatistics statisticsFromJsonText(const std::string& text, const std::string& source);

/// Outcome of a comparison with the golden statistics.
struct RegressionResult {
  /// kPass: every statistic within tolerance; kFail: at least one is not.
  enum class Status { kPass, kFail };
  Status status = Status::kPass;    ///< the verdict
  std::string message;              ///< "<n> statistic(s) failed" or empty
  std::vector<ComparisonRow> rows;  ///< one per statistic, in the printed order
};

/// compareStatistics with a verdict.
RegressionResult compareWithGolden(const std::string& case_name, const MapStatistics& golden,
                                   const MapStatistics& now);

/// Compares now against golden with the suite's stated tolerances (see regression.cpp).
std::vector<ComparisonRow> compareStatistics(const std::string& case_name,
                                             const MapStatistics& golden, const MapStatistics& now);

/// Reads the case list; throws Error naming the file on a bad entry.
std::vector<RegressionCase> readCases(const std::string& path);

}  // namespace taskmap
