#pragma once
/// @file component_boruvka.hpp
/// Private to emst.cpp: the end of the EMST, once components are few and large.
///
/// In the global kd-tree, leaves that straddle two components have boxes spanning the gap
/// between them, so proving "no foreign point nearer than the component's best edge" visits
/// many leaves in vain. Here every component gets its own kd-tree (tight boxes), and the
/// shortest edge between two components is a bichromatic closest pair found by a dual-tree
/// search between their trees, computed lazily by Kruskal (completeByComponents).

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

  /// @param roots_distance the box distance of the two roots.
  void run(EdgeKey& best, double roots_distance) {
    best_ = best;
    visit(0, 0, roots_distance);
    best = best_;
  }

 private:
  /// @param lower the box distance of (na, nb), computed by the caller.
  void visit(int na, int nb, double lower) {
    if (lower > best_.d2) return;
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
      const double d_left = boxBoxDistance2(a_, node_a.left, b_, nb);
      const double d_right = boxBoxDistance2(a_, node_a.right, b_, nb);
      if (d_right < d_left) {
        visit(node_a.right, nb, d_right);
        visit(node_a.left, nb, d_left);
      } else {
        visit(node_a.left, nb, d_left);
        visit(node_a.right, nb, d_right);
      }
    } else {
      const double d_left = boxBoxDistance2(a_, na, b_, node_b.left);
      const double d_right = boxBoxDistance2(a_, na, b_, node_b.right);
      if (d_right < d_left) {
        visit(na, node_b.right, d_right);
        visit(na, node_b.left, d_left);
      } else {
        visit(na, node_b.left, d_left);
        visit(na, node_b.right, d_right);
      }
    }
  }

  const KdTree<D>& a_;
  const KdTree<D>& b_;
  const std::vector<int>& rows_a_;  // tree row -> row of the full point matrix
  const std::vector<int>& rows_b_;
  EdgeKey best_;
};

/// Completes a spanning forest (edges with squared lengths, endpoints as rows of points)
/// to the minimum spanning tree: Kruskal on the graph of the forest's components, whose
/// edge between two components is their closest pair. Pairs enter a queue keyed by the
/// distance of their root boxes (a lower bound); a pair popped with its lower bound is
/// dropped if its components are joined already (its exact edge, not shorter, would be
/// rejected then too), else its closest pair is computed and queued with the exact key. An
/// exact key popped is the shortest remaining edge: Kruskal takes it if it joins two
/// components. Each closest pair is computed at most once.
template <int D>
void completeByComponents(const PointMatrix& points, std::vector<EdgeKey>& edges) {
  const int n = static_cast<int>(points.rows());
  UnionFind uf(n);
  for (const EdgeKey& e : edges) uf.unite(e.lo, e.hi);
  int components = n - static_cast<int>(edges.size());
  if (components <= 1) return;
  // Components in order of their smallest row; members in row order.
  std::vector<int> id_of_root(n, -1);
  std::vector<std::vector<int>> members;
  for (int i = 0; i < n; ++i) {
    int& id = id_of_root[uf.find(i)];
    if (id < 0) {
      id = static_cast<int>(members.size());
      members.emplace_back();
    }
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
  // Queue entry: key, the two components, and whether the key is exact. A lower bound sorts
  // before an exact key of the same length (lo = hi = -1).
  struct Entry {
    EdgeKey key;
    int a;
    int b;
    bool exact;
  };
  auto later = [](const Entry& x, const Entry& y) {
    if (x.key.d2 != y.key.d2) return x.key.d2 > y.key.d2;
    if (x.key.lo != y.key.lo) return x.key.lo > y.key.lo;
    return x.key.hi > y.key.hi;
  };
  std::vector<Entry> heap;
  heap.reserve(static_cast<std::size_t>(m) * (m - 1) / 2);
  for (int a = 0; a < m; ++a) {
    for (int b = a + 1; b < m; ++b) {
      heap.push_back(
          Entry{EdgeKey{boxBoxDistance2(trees[a], 0, trees[b], 0), -1, -1}, a, b, false});
    }
  }
  std::make_heap(heap.begin(), heap.end(), later);
  while (components > 1) {
    assert(!heap.empty());
    std::pop_heap(heap.begin(), heap.end(), later);
    Entry e = heap.back();
    heap.pop_back();
    const int ra = members[e.a].front();
    const int rb = members[e.b].front();
    if (uf.find(ra) == uf.find(rb)) continue;
    if (e.exact) {
      uf.unite(ra, rb);
      edges.push_back(e.key);
      --components;
      continue;
    }
    const double lower = e.key.d2;
    e.key = EdgeKey{};
    ClosestPair<D> search(trees[e.a], members[e.a], trees[e.b], members[e.b]);
    search.run(e.key, lower);
    e.exact = true;
    heap.push_back(e);
    std::push_heap(heap.begin(), heap.end(), later);
  }
}

}  // namespace taskmap::detail::emst
