// Euclidean minimum spanning tree: dual-tree Borůvka over a kd-tree, finished by Kruskal
// over per-component kd-trees (component_boruvka.hpp).
//
// Why our own kd-tree and not FLANN's: every Borůvka round asks, for each point, "nearest
// neighbour NOT in my component". FLANN's exact kd-tree (KDTreeSingleIndex) only answers
// plain k-NN / radius queries; filtering by component would need k to grow until a foreign
// point shows up, which degenerates to O(n) per query once components are large. Here each
// node knows whether all its points lie in one component, so pairs of nodes inside one
// component are pruned, and each query is bounded by its component's best edge so far (the
// dual-tree bound of March, Ram and Gray, "Fast Euclidean minimum spanning tree", KDD 2010).
// Both prunings need the tree's nodes, which FLANN does not expose. The brute-force O(n^2)
// Prim oracle in tests/unit/clustering/linkage_test.cpp checks the result.
//
// Phases:
//  1. k nearest neighbours of every point (kNeighbours): the first foreign entry of a
//     point's list is its exact nearest foreign point, which answers the first rounds
//     without tree searches; an exhausted list gives a lower bound.
//  2. Dual-tree Borůvka rounds. A point's exact nearest foreign point stays exact while that
//     point stays foreign (the own component only grows), so it is cached across rounds;
//     a bounded search that finds nothing raises the point's lower bound, and a point whose
//     lower bound exceeds its component's best edge is not searched.
//  3. Once few components remain (kComponentPhase), Kruskal over closest pairs between
//     per-component trees (component_boruvka.hpp), whose boxes are tight.
// Ties are broken by a strict total order on edges (d^2, min index, max index), which makes
// the MST unique and Borůvka's simultaneous merges cycle-free. The result depends neither on
// the processing order, the cached state nor the thread count, only on the points.

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <thread>
#include <vector>

#include "component_boruvka.hpp"
#include "kd_tree.hpp"
#include "linkage_internal.hpp"

namespace taskmap::detail {
namespace {

using emst::EdgeKey;
using emst::KdTree;
using emst::kLeafSize;
using emst::kNeighbours;

/// Points from which the neighbour lists are computed by several threads.
constexpr int kParallelPoints = 2000;

/// Threads for the neighbour lists: the hardware's, at most 8.
int workerThreads() {
  const unsigned hw = std::thread::hardware_concurrency();
  return static_cast<int>(std::clamp(hw, 1u, 8u));
}

/// Components at which the rounds switch to per-component trees (component_boruvka.hpp).
constexpr int kComponentPhase = 3000;
using emst::kNoPoint;
using emst::UnionFind;

template <int D>
class DualTreeBoruvka {
 public:
  using Tree = KdTree<D>;
  using Node = typename Tree::Node;
  explicit DualTreeBoruvka(const Tree& tree)
      : tree_(tree),
        nodes_(tree.nodes()),
        n_(tree.size()),
        comp_(n_),
        node_comp_(nodes_.size(), -1),
        node_bound_(nodes_.size(), 0.0),
        cached_(n_, -1),
        cached_d2_(n_, 0.0),
        lower_(n_, 0.0),
        query_d2_(n_, 0.0),
        query_best_(n_, kNoPoint),
        needs_query_(n_, 0),
        best_(n_),
        uf_(n_) {
    std::iota(comp_.begin(), comp_.end(), 0);
    k_ = std::min(kNeighbours, n_ - 1);
    neighbours_.resize(static_cast<std::size_t>(n_) * k_);
    neighbour_d2_.resize(neighbours_.size());
    // Each point's list depends on the tree alone, so splitting the points among threads
    // cannot change the result.
    auto lists = [this](int begin, int end) {
      for (int p = begin; p < end; ++p) {
        const std::size_t at = static_cast<std::size_t>(p) * k_;
        tree_.nearest(p, k_, &neighbours_[at], &neighbour_d2_[at]);
      }
    };
    const int threads = n_ >= kParallelPoints ? workerThreads() : 1;
    std::vector<std::thread> workers;
    for (int t = 1; t < threads; ++t) {
      workers.emplace_back(lists, static_cast<int>(static_cast<std::int64_t>(n_) * t / threads),
                           static_cast<int>(static_cast<std::int64_t>(n_) * (t + 1) / threads));
    }
    lists(0, n_ / threads);
    for (std::thread& w : workers) w.join();
  }

  /// Spanning forest edges as (tree position, tree position, squared length), after rounds
  /// until at most stop_components components remain.
  std::vector<EdgeKey> run(int stop_components) {
    std::vector<EdgeKey> edges;
    edges.reserve(n_ - 1);
    int components = n_;
    std::vector<int> roots;
    while (components > std::max(1, stop_components)) {
      updateNodeComponents();
      roots.clear();
      for (int p = 0; p < n_; ++p) {
        if (comp_[p] == p) {
          roots.push_back(p);
          best_[p] = EdgeKey{};
        }
      }
      // Pass 1: exact nearest foreign points from the cache or the neighbour list.
      for (int p = 0; p < n_; ++p) {
        const int c = comp_[p];
        const int j = cached_[p];
        if (j >= 0 && comp_[j] != c) {
          offer(p, j, cached_d2_[p]);
          continue;
        }
        cached_[p] = -1;
        // The list holds the k smallest (d^2, position) keys: its first foreign entry is the
        // exact nearest foreign point; without one, every foreign point is at least as far
        // as the last entry.
        const std::size_t at = static_cast<std::size_t>(p) * k_;
        for (int t = 0; t < k_; ++t) {
          const int r = neighbours_[at + t];
          if (comp_[r] != c) {
            cached_[p] = r;
            cached_d2_[p] = neighbour_d2_[at + t];
            offer(p, r, cached_d2_[p]);
            break;
          }
        }
        if (cached_[p] < 0) lower_[p] = std::max(lower_[p], neighbour_d2_[at + k_ - 1]);
      }
      // Pass 2: points that could still beat their component's best edge are queried.
      for (int p = 0; p < n_; ++p) {
        const EdgeKey& b = best_[comp_[p]];
        needs_query_[p] = cached_[p] < 0 && lower_[p] <= b.d2;
        query_d2_[p] = b.d2;
        query_best_[p] = kNoPoint;
      }
      updateNodeBounds();
      traverse(0, 0);
      for (int p = 0; p < n_; ++p) {
        if (!needs_query_[p]) continue;
        const double component_best = best_[comp_[p]].d2;
        if (query_best_[p] != kNoPoint && query_d2_[p] <= component_best) {
          // Found within every bound the search used: the exact nearest foreign point.
          cached_[p] = query_best_[p];
          cached_d2_[p] = query_d2_[p];
          lower_[p] = query_d2_[p];
        } else {
          // Everything nearer than the component's best edge was searched and is own.
          lower_[p] = std::max(lower_[p], component_best);
        }
      }
      for (int c : roots) {
        const EdgeKey& e = best_[c];
        assert(e.lo != kNoPoint);
        if (uf_.unite(e.lo, e.hi)) {
          edges.push_back(e);
          --components;
        }
      }
      for (int p = 0; p < n_; ++p) comp_[p] = uf_.find(p);
    }
    return edges;
  }

 private:
  void offer(int p, int j, double d2) {
    const EdgeKey key{d2, std::min(p, j), std::max(p, j)};
    EdgeKey& b = best_[comp_[p]];
    if (key < b) b = key;
  }

  /// node_comp_: the component of a node whose points all share one, else -1.
  void updateNodeComponents() {
    for (int v = static_cast<int>(nodes_.size()) - 1; v >= 0; --v) {
      const Node& nd = nodes_[v];
      if (nd.left < 0) {
        int c = comp_[nd.begin];
        for (int p = nd.begin + 1; p < nd.end && c >= 0; ++p) {
          if (comp_[p] != c) c = -1;
        }
        node_comp_[v] = c;
      } else {
        const int a = node_comp_[nd.left];
        node_comp_[v] = (a >= 0 && a == node_comp_[nd.right]) ? a : -1;
      }
    }
  }

  /// node_bound_: the largest query bound of the node's queried points (-1: none); it only
  /// shrinks during a round, so a stale (larger) value is safe.
  double leafBound(int v) const {
    const Node& nd = nodes_[v];
    double b = -1.0;
    for (int p = nd.begin; p < nd.end; ++p) {
      if (needs_query_[p]) b = std::max(b, queryBound(p));
    }
    return b;
  }
  void updateNodeBounds() {
    for (int v = static_cast<int>(nodes_.size()) - 1; v >= 0; --v) {
      const Node& nd = nodes_[v];
      node_bound_[v] =
          nd.left < 0 ? leafBound(v) : std::max(node_bound_[nd.left], node_bound_[nd.right]);
    }
  }

  /// Bound of a queried point: its best so far, capped by its component's best edge (the
  /// search only needs points that could improve the component's edge).
  double queryBound(int p) const { return std::min(query_d2_[p], best_[comp_[p]].d2); }

  void baseCase(int q_node, int r_node) {
    const Node& qn = nodes_[q_node];
    const Node& rn = nodes_[r_node];
    for (int q = qn.begin; q < qn.end; ++q) {
      if (!needs_query_[q]) continue;
      const int own = comp_[q];
      const double* x = tree_.point(q);
      // Point-to-box test first: most reference leaves are out of reach of most points.
      if (tree_.boxDistance2(r_node, x) > queryBound(q)) continue;
      for (int r = rn.begin; r < rn.end; ++r) {
        if (comp_[r] == own) continue;
        const double d2 = tree_.distance2(x, tree_.point(r));
        // Accept equal distances: they may come with a lower index.
        if ((d2 < query_d2_[q] || (d2 == query_d2_[q] && r < query_best_[q])) &&
            d2 <= best_[own].d2) {
          query_d2_[q] = d2;
          query_best_[q] = r;
          offer(q, r, d2);
        }
      }
    }
    node_bound_[q_node] = leafBound(q_node);
  }

  void traverse(int q_node, int r_node) {
    if (node_bound_[q_node] < 0.0) return;
    const int cq = node_comp_[q_node];
    if (cq >= 0 && cq == node_comp_[r_node]) return;
    if (tree_.boxBoxDistance2(q_node, r_node) > node_bound_[q_node]) return;
    const Node& qn = nodes_[q_node];
    const Node& rn = nodes_[r_node];
    const bool q_leaf = qn.left < 0;
    const bool r_leaf = rn.left < 0;
    if (q_leaf && r_leaf) {
      baseCase(q_node, r_node);
      return;
    }
    if (r_leaf || (!q_leaf && qn.end - qn.begin >= rn.end - rn.begin)) {
      traverse(qn.left, r_node);
      traverse(qn.right, r_node);
      node_bound_[q_node] = std::max(node_bound_[qn.left], node_bound_[qn.right]);
      return;
    }
    int near = rn.left;
    int far = rn.right;
    if (tree_.boxBoxDistance2(q_node, far) < tree_.boxBoxDistance2(q_node, near)) {
      std::swap(near, far);
    }
    traverse(q_node, near);
    traverse(q_node, far);
  }

  const Tree& tree_;
  const std::vector<Node>& nodes_;
  int n_;
  std::vector<int> comp_;  // component (a union-find root) of each tree position
  std::vector<int> node_comp_;
  std::vector<double> node_bound_;
  std::vector<int> cached_;  // exact nearest foreign point, -1 if unknown
  std::vector<double> cached_d2_;
  std::vector<double> lower_;     // lower bound on the squared nearest foreign distance
  std::vector<double> query_d2_;  // this round: bound, then the best squared distance
  std::vector<int> query_best_;   // this round: best point found (kNoPoint: none)
  std::vector<char> needs_query_;
  std::vector<EdgeKey> best_;  // per component root
  UnionFind uf_;
  int k_ = 0;                    // neighbours per point in the lists
  std::vector<int> neighbours_;  // n x k nearest other points, sorted by (d^2, position)
  std::vector<double> neighbour_d2_;
};

template <int D>
std::vector<PointMerge> mstOf(const PointMatrix& points) {
  const KdTree<D> tree(points);
  DualTreeBoruvka<D> boruvka(tree);
  const int stop = std::min(kComponentPhase, static_cast<int>(points.rows()) / kLeafSize);
  std::vector<EdgeKey> forest = boruvka.run(stop);
  for (EdgeKey& e : forest) {
    const int a = tree.original(e.lo);
    const int b = tree.original(e.hi);
    e.lo = std::min(a, b);
    e.hi = std::max(a, b);
  }
  emst::completeByComponents<D>(points, forest);
  assert(static_cast<Eigen::Index>(forest.size()) == points.rows() - 1);
  std::vector<PointMerge> edges;
  edges.reserve(forest.size());
  for (const EdgeKey& e : forest) edges.push_back(PointMerge{e.lo, e.hi, e.d2});
  // Sort by (d^2, a, b) on original indices, then take square roots.
  std::sort(edges.begin(), edges.end(), [](const PointMerge& x, const PointMerge& y) {
    if (x.d != y.d) return x.d < y.d;
    if (x.a != y.a) return x.a < y.a;
    return x.b < y.b;
  });
  for (PointMerge& e : edges) e.d = std::sqrt(e.d);
  return edges;
}

}  // namespace

std::vector<PointMerge> euclideanMst(const PointMatrix& points) {
  [[maybe_unused]] const int n = static_cast<int>(points.rows());
  assert(n >= 2);
  if (points.cols() == kEmbeddingDim) return mstOf<kEmbeddingDim>(points);
  return mstOf<0>(points);
}

}  // namespace taskmap::detail
