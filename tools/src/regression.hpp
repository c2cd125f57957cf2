#pragma once
/// @file regression.hpp
/// Regression suite on reference objects: build a small map per (object, hand) case with a
/// fixed seed and trial budget, reduce it to golden statistics, compare with checked-in ones.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap::cli {

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
  std::uint64_t trials = 0;
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
  std::string case_name, statistic, golden, now;
  bool pass = true;
};

/// Reduces a map to its statistics (quantiles: linear interpolation, numpy's default).
MapStatistics computeStatistics(const TaskMapData& map);
/// Statistics to and from the golden JSON layout.
nlohmann::json toJson(const MapStatistics& s);
MapStatistics statisticsFromJson(const nlohmann::json& j, const std::string& source);

/// Compares now against golden with the suite's stated tolerances (see regression.cpp).
std::vector<ComparisonRow> compareStatistics(const std::string& case_name,
                                             const MapStatistics& golden, const MapStatistics& now);

/// Reads the case list; throws Error naming the file on a bad entry.
std::vector<RegressionCase> readCases(const std::string& path);

}  // namespace taskmap::cli
