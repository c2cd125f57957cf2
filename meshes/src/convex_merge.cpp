// Capping the piece count of a convex decomposition: the pair of pieces whose joint convex hull
// adds the least volume (vol(hull(A u B)) - vol(A) - vol(B)) merges first, among pairs whose
// bounding boxes touch (neighbours) while there are any, else among all pairs. Ties go to the
// lowest indices, so the result does not depend on anything but the input order.
#include <algorithm>
#include <limits>
#include <map>
#include <utility>

#include <Eigen/Geometry>

#include "convex_decomposition.hpp"

namespace taskmap::detail {
namespace {

Eigen::AlignedBox3d boxOf(const PointHull& h) {
  Eigen::AlignedBox3d b;
  for (const auto& p : h.vertices) b.extend(p);
  return b;
}

bool touch(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b, double tol) {
  return (a.min().array() <= b.max().array() + tol).all() &&
         (b.min().array() <= a.max().array() + tol).all();
}

PointHull joined(const PointHull& a, const PointHull& b, const std::string& what) {
  std::vector<Eigen::Vector3d> pts = a.vertices;
  pts.insert(pts.end(), b.vertices.begin(), b.vertices.end());
  return convexHull(pts, what + " (merged convex pieces)");
}

/// Alive pieces and the added volume of merging each candidate pair.
struct MergeState {
  std::vector<PointHull> pieces;
  std::vector<Eigen::AlignedBox3d> boxes;
  std::vector<bool> alive;
  std::map<std::pair<int, int>, double> cost;  ///< (i < j) -> added volume, neighbours only
  double tol = 0.0;

  void addPairs(int j, bool neighbours_only, const std::string& what) {
    for (int i = 0; i < j; ++i) {
      const auto ui = static_cast<std::size_t>(i), uj = static_cast<std::size_t>(j);
      if (!alive[ui] || (neighbours_only && !touch(boxes[ui], boxes[uj], tol))) continue;
      const PointHull h = joined(pieces[ui], pieces[uj], what);
      cost[{i, j}] = h.volume - pieces[ui].volume - pieces[uj].volume;
    }
  }

  /// Merges the cheapest pair into a new piece; false when no candidate pair is left.
  bool mergeCheapest(const std::string& what) {
    auto best = cost.end();
    double best_cost = std::numeric_limits<double>::infinity();
    for (auto it = cost.begin(); it != cost.end(); ++it)
      if (it->second < best_cost) best_cost = it->second, best = it;
    if (best == cost.end()) return false;
    const auto [i, j] = best->first;
    pieces.push_back(
        joined(pieces[static_cast<std::size_t>(i)], pieces[static_cast<std::size_t>(j)], what));
    boxes.push_back(boxOf(pieces.back()));
    alive[static_cast<std::size_t>(i)] = alive[static_cast<std::size_t>(j)] = false;
    alive.push_back(true);
    for (auto it = cost.begin(); it != cost.end();)
      it = (it->first.first == i || it->first.first == j || it->first.second == i ||
            it->first.second == j)
               ? cost.erase(it)
               : std::next(it);
    addPairs(static_cast<int>(pieces.size()) - 1, true, what);
    return true;
  }

  int count() const { return static_cast<int>(std::count(alive.begin(), alive.end(), true)); }
};

}  // namespace

std::vector<PointHull> mergePieces(std::vector<PointHull> pieces, int max_pieces,
                                   const std::string& what) {
  if (max_pieces < 1 || static_cast<int>(pieces.size()) <= max_pieces) return pieces;
  MergeState s;
  s.pieces = std::move(pieces);
  Eigen::AlignedBox3d all;
  for (const auto& p : s.pieces) {
    s.boxes.push_back(boxOf(p));
    all.extend(s.boxes.back());
  }
  s.tol = 1e-6 * all.diagonal().norm();
  s.alive.assign(s.pieces.size(), true);
  for (int j = 0; j < static_cast<int>(s.pieces.size()); ++j) s.addPairs(j, true, what);
  while (s.count() > max_pieces) {
    if (s.mergeCheapest(what)) continue;
    // No two alive pieces touch: consider every pair.
    for (int j = 0; j < static_cast<int>(s.pieces.size()); ++j)
      if (s.alive[static_cast<std::size_t>(j)]) s.addPairs(j, false, what);
    if (!s.mergeCheapest(what)) break;
  }
  std::vector<PointHull> out;
  for (std::size_t k = 0; k < s.pieces.size(); ++k)
    if (s.alive[k]) out.push_back(std::move(s.pieces[k]));
  return out;
}

}  // namespace taskmap::detail
