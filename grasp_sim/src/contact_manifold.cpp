#include "taskmap/grasp_sim/contact_manifold.hpp"

#include <algorithm>
#include <limits>

#include <Eigen/Geometry>

namespace taskmap {

std::vector<Contact> contactManifold(const std::vector<Contact>& candidates, int max_points) {
  const std::size_t n = candidates.size();
  if (max_points <= 0 || n <= static_cast<std::size_t>(max_points)) return candidates;
  std::vector<char> chosen(n, 0);
  std::vector<std::size_t> picks{0};  // the deepest
  chosen[0] = 1;
  auto pickBest = [&](auto score) {
    std::size_t best = n;
    double best_score = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i) {
      if (chosen[i]) continue;
      const double s = score(candidates[i].point);
      if (s > best_score) {
        best_score = s;
        best = i;
      }
    }
    chosen[best] = 1;
    picks.push_back(best);
  };
  const Eigen::Vector3d p0 = candidates[0].point;
  pickBest([&](const Eigen::Vector3d& p) { return (p - p0).squaredNorm(); });
  if (picks.size() < static_cast<std::size_t>(max_points)) {
    const Eigen::Vector3d p1 = candidates[picks[1]].point;
    pickBest([&](const Eigen::Vector3d& p) { return (p1 - p0).cross(p - p0).squaredNorm(); });
  }
  while (picks.size() < static_cast<std::size_t>(max_points)) {
    pickBest([&](const Eigen::Vector3d& p) {
      double nearest = std::numeric_limits<double>::infinity();
      for (std::size_t k : picks)
        nearest = std::min(nearest, (p - candidates[k].point).squaredNorm());
      return nearest;
    });
  }
  std::sort(picks.begin(), picks.end());
  std::vector<Contact> out;
  out.reserve(picks.size());
  for (std::size_t k : picks) out.push_back(candidates[k]);
  return out;
}

}  // namespace taskmap
