#pragma once
/// @file component_boruvka.hpp
/// Private to emst.cpp: the last Borůvka rounds, once components are few and large.
///
/// In the global kd-tree, leaves that straddle two components have boxes spanning the gap
/// between them, so proving "no foreign point nearer than the component's best edge" visits
/// many leaves in vain. Here every component gets its own kd-tree (tight boxes), and the
/// shortest edge between two components is a bichromatic closest pair found by a dual-tree
/// search between their trees, bounded by the best edges found so far. Component pairs are
/// visited in order of their root-box distance and skipped when that bound exceeds both
/// components' best edges.

#include <algorithm>
#include <utility>
#include <vector>

#include "kd_tree.hpp"

namespace taskmap::detail::emst {

/// Closest pair between two kd-trees under the edge order (d^2, lo, hi) on original rows;
/// best holds the bound on entry and the best edge found on exit (unchanged if none is
/// smaller).
template <int D>
class ClosestPair {
 public:
  ClosestPair(const KdTree<D>& a, const std::vector<int>& rows_a, const KdTree<D>& b,
              const std::vector<int>& rows_b)
      : a_(a), b_(b), rows_a_(rows_a), rows_b_(rows_b) {}

  void run(EdgeKey& best) {
    best_ = best;
    visit(0, 0);
    best = best_;
  }

 private:
  void visit(int na, int nb) {
    if (boxBoxDistance2(a_, na, b_, nb) > best_.d2) return;
    const auto& node_a = a_.nodes()[na];
    const auto& node_b = b_.nodes()[nb];
    const bool leaf_a = node_a.left < 0;
    const bool leaf_b = node_b.left < 0;
    if (leaf_a && leaf_b) {
      for (int p = node_a.begin; p < node_a.end; ++p) {
        const double* x = a_.point(p);
        if (b_.boxDistance2(nb, x) > best_.d2) continue;
        const int ra = rows_a_[a_.original(p)];
        for (int r = node_b.begin; r < node_b.end; ++r) {
          const double d2 = a_.distance2(x, b_.point(r));
          if (d2 > best_.d2) continue;
          const int rb = rows_b_[b_.original(r)];
          const EdgeKey key{d2, std::min(ra, rb), std::max(ra, rb)};
          if (key < best_) best_ = key;
        }
      }
      return;
    }
    const bool split_a =
        leaf_b || (!leaf_a && node_a.end - node_a.begin >= node_b.end - node_b.begin);
    if (split_a) {
      int first = node_a.left;
      int second = node_a.right;
      if (boxBoxDistance2(a_, second, b_, nb) < boxBoxDistance2(a_, first, b_, nb)) {
        std::swap(first, second);
      }
      visit(first, nb);
      visit(second, nb);
    } else {
      int first = node_b.left;
      int second = node_b.right;
      if (boxBoxDistance2(a_, na, b_, second) < boxBoxDistance2(a_, na, b_, first)) {
        std::swap(first, second);
      }
      visit(na, first);
      visit(na, second);
    }
  }

  const KdTree<D>& a_;
  const KdTree<D>& b_;
  const std::vector<int>& rows_a_;  // tree row -> row of the full point matrix
  const std::vector<int>& rows_b_;
  EdgeKey best_;
};

/// Completes a spanning forest (edges with squared lengths, endpoints as rows of points)
/// to the minimum spanning tree by Borůvka rounds over per-component kd-trees.
template <int D>
void completeByComponents(const PointMatrix& points, std::vector<EdgeKey>& edges) {
  const int n = static_cast<int>(points.rows());
  UnionFind uf(n);
  for (const EdgeKey& e : edges) uf.unite(e.lo, e.hi);
  int components = n - static_cast<int>(edges.size());
  std::vector<int> comp_of(n);
  while (components > 1) {
    // Components in order of their smallest row; members in row order.
    std::vector<int> id_of_root(n, -1);
    std::vector<std::vector<int>> members;
    for (int i = 0; i < n; ++i) {
      int& id = id_of_root[uf.find(i)];
      if (id < 0) {
        id = static_cast<int>(members.size());
        members.emplace_back();
      }
      comp_of[i] = id;
      members[id].push_back(i);
    }
    const int m = static_cast<int>(members.size());
    std::vector<KdTree<D>> trees;
    trees.reserve(m);
    for (int c = 0; c < m; ++c) {
      PointMatrix sub(static_cast<Eigen::Index>(members[c].size()), points.cols());
      for (std::size_t t = 0; t < members[c].size(); ++t) sub.row(t) = points.row(members[c][t]);
      trees.emplace_back(sub);
    }
    // Component pairs by the distance of their root boxes.
    std::vector<std::pair<double, std::pair<int, int>>> pairs;
    pairs.reserve(static_cast<std::size_t>(m) * (m - 1) / 2);
    for (int a = 0; a < m; ++a) {
      for (int b = a + 1; b < m; ++b) {
        pairs.push_back({boxBoxDistance2(trees[a], 0, trees[b], 0), {a, b}});
      }
    }
    std::sort(pairs.begin(), pairs.end());
    std::vector<EdgeKey> best(m);
    for (const auto& entry : pairs) {
      const int a = entry.second.first;
      const int b = entry.second.second;
      // Only a pair that can beat one of the two components' best edges is searched.
      EdgeKey bound = best[a] < best[b] ? best[b] : best[a];
      if (entry.first > bound.d2) continue;
      ClosestPair<D> search(trees[a], members[a], trees[b], members[b]);
      search.run(bound);
      if (bound < best[a]) best[a] = bound;
      if (bound < best[b]) best[b] = bound;
    }
    for (int c = 0; c < m; ++c) {
      assert(best[c].lo != kNoPoint);
      if (uf.unite(best[c].lo, best[c].hi)) {
        edges.push_back(best[c]);
        --components;
      }
    }
  }
}

}  // namespace taskmap::detail::emst
