#pragma once
// Assembling a page: HTML skeleton, inlined scripts, data as JSON, rounded numbers.

#include <cstdint>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "taskmap/core/pose.hpp"
#include "taskmap/viz/page_options.hpp"

namespace taskmap::viz_detail {

/// x rounded to `decimals` places (so the JSON stays short).
double rounded(double x, int decimals);

/// The values of a matrix, row by row, rounded.
template <typename Matrix>
nlohmann::json flat(const Matrix& m, int decimals) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index k = 0; k < m.cols(); ++k)
      out.push_back(rounded(static_cast<double>(m(i, k)), decimals));
  return out;
}

/// The values of an integer matrix, row by row.
template <typename Matrix>
nlohmann::json flatInt(const Matrix& m) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index k = 0; k < m.cols(); ++k) out.push_back(static_cast<std::int64_t>(m(i, k)));
  return out;
}

/// x y z qw qx qy qz of a pose, rounded.
nlohmann::json poseJson(const Pose& p, int decimals);

/// The whole page: title, the viewer's CSS, #tm-error, three.js (its licence in a comment),
/// `data` in <script type="application/json" id="tm-data">, viewer_common.js and the page's own
/// script resource `script` (viewer_map_js, ...). Throws Error when three.js is missing.
std::string assemblePage(const std::string& title, const std::string& script,
                         const nlohmann::json& data);

/// Writes html to path atomically; throws Error naming the path.
void writePage(const std::string& html, const std::string& path);

}  // namespace taskmap::viz_detail
