#pragma once
/// @file kd_tree.hpp
/// Private to emst.cpp: the kd-tree, union-find and edge order of the Borůvka EMST.

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "taskmap/clustering/clustering.hpp"

namespace taskmap::detail::emst {

constexpr int kLeafSize = 32;
constexpr int kNoPoint = std::numeric_limits<int>::max();
/// Nearest neighbours listed per point: they answer most "nearest foreign point" questions
/// of the middle rounds without a tree search.
constexpr int kNeighbours = 4;

/// Coordinates per point: D > 0 fixed at compile time (the 12-D pose embedding, so that the
/// distance loops unroll), D = 0 taken from the point matrix.
template <int D>
struct Dim {
  explicit Dim(int d) : value(D > 0 ? D : d) {}
  int value;
  constexpr int get() const { return D > 0 ? D : value; }
};

/// kd-tree over a private, tree-ordered copy of the points (position p = p-th point in tree
/// order). Nodes in pre-order: children have larger indices than their parent.
template <int D>
class KdTree {
 public:
  struct Node {
    int begin = 0;
    int end = 0;
    int left = -1;  ///< -1 for a leaf
    int right = -1;
  };

  explicit KdTree(const PointMatrix& points)
      : n_(static_cast<int>(points.rows())), dim_(static_cast<int>(points.cols())) {
    assert(D == 0 || D == points.cols());
    order_.resize(n_);
    std::iota(order_.begin(), order_.end(), 0);
    nodes_.reserve(2 * static_cast<std::size_t>(n_) / kLeafSize + 2);
    build(points, 0, n_);
    leaf_of_.resize(n_);
    for (int v = 0; v < static_cast<int>(nodes_.size()); ++v) {
      if (nodes_[v].left >= 0) continue;
      for (int p = nodes_[v].begin; p < nodes_[v].end; ++p) leaf_of_[p] = v;
    }
    data_.resize(static_cast<std::size_t>(n_) * dim_.get());
    for (int p = 0; p < n_; ++p) {
      for (int k = 0; k < dim_.get(); ++k)
        data_[static_cast<std::size_t>(p) * dim_.get() + k] = points(order_[p], k);
    }
  }

  int size() const { return n_; }
  int dim() const { return dim_.get(); }
  const std::vector<Node>& nodes() const { return nodes_; }
  const double* point(int p) const { return &data_[static_cast<std::size_t>(p) * dim_.get()]; }
  const double* lo(int node) const { return &lo_[static_cast<std::size_t>(node) * dim_.get()]; }
  const double* hi(int node) const { return &hi_[static_cast<std::size_t>(node) * dim_.get()]; }
  /// Row of the point matrix at tree position p.
  int original(int p) const { return order_[p]; }

  /// Squared distance from q to the node's bounding box.
  double boxDistance2(int node, const double* q) const {
    const double* l = lo(node);
    const double* h = hi(node);
    double s = 0.0;
    for (int k = 0; k < dim_.get(); ++k) {
      const double e = std::max(std::max(l[k] - q[k], q[k] - h[k]), 0.0);
      s += e * e;
    }
    return s;
  }

  /// The k nearest other points of tree position p, by (squared distance, position), into
  /// idx/d2 (k entries; -1 / infinity past the end when there are fewer points).
  void nearest(int p, int k, int* idx, double* d2) const {
    for (int t = 0; t < k; ++t) {
      idx[t] = -1;
      d2[t] = std::numeric_limits<double>::infinity();
    }
    // Seed with the point's own leaf for a tight bound, then search the rest of the tree.
    const int leaf = leaf_of_[p];
    nearestIn(leaf, p, point(p), k, idx, d2, -1);
    nearestIn(0, p, point(p), k, idx, d2, leaf);
  }

  /// Squared distance between the bounding boxes of two nodes.
  double boxBoxDistance2(int a, int b) const {
    const double* la = lo(a);
    const double* ha = hi(a);
    const double* lb = lo(b);
    const double* hb = hi(b);
    double s = 0.0;
    for (int k = 0; k < dim_.get(); ++k) {
      const double e = std::max(std::max(la[k] - hb[k], lb[k] - ha[k]), 0.0);
      s += e * e;
    }
    return s;
  }

  double distance2(const double* a, const double* b) const {
    double s = 0.0;
    for (int k = 0; k < dim_.get(); ++k) {
      const double e = a[k] - b[k];
      s += e * e;
    }
    return s;
  }

 private:
  void nearestIn(int node, int p, const double* q, int k, int* idx, double* d2, int skip) const {
    const Node& nd = nodes_[node];
    if (nd.left < 0) {
      if (node == skip) return;
      for (int r = nd.begin; r < nd.end; ++r) {
        if (r == p) continue;
        const double d = distance2(q, point(r));
        if (d > d2[k - 1] || (d == d2[k - 1] && r > idx[k - 1] && idx[k - 1] >= 0)) continue;
        int t = k - 1;  // insertion into the sorted list
        while (t > 0 && (d < d2[t - 1] || (d == d2[t - 1] && r < idx[t - 1]))) {
          d2[t] = d2[t - 1];
          idx[t] = idx[t - 1];
          --t;
        }
        d2[t] = d;
        idx[t] = r;
      }
      return;
    }
    int first = nd.left;
    int second = nd.right;
    double d_first = boxDistance2(first, q);
    double d_second = boxDistance2(second, q);
    if (d_second < d_first) {
      std::swap(first, second);
      std::swap(d_first, d_second);
    }
    if (d_first <= d2[k - 1]) nearestIn(first, p, q, k, idx, d2, skip);
    if (d_second <= d2[k - 1]) nearestIn(second, p, q, k, idx, d2, skip);
  }

  int build(const PointMatrix& points, int begin, int end) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.push_back(Node{begin, end, -1, -1});
    lo_.resize(lo_.size() + dim_.get());
    hi_.resize(hi_.size() + dim_.get());
    double* l = &lo_[static_cast<std::size_t>(id) * dim_.get()];
    double* h = &hi_[static_cast<std::size_t>(id) * dim_.get()];
    for (int k = 0; k < dim_.get(); ++k) {
      l[k] = std::numeric_limits<double>::infinity();
      h[k] = -std::numeric_limits<double>::infinity();
    }
    for (int p = begin; p < end; ++p) {
      const int row = order_[p];
      for (int k = 0; k < dim_.get(); ++k) {
        const double v = points(row, k);
        l[k] = std::min(l[k], v);
        h[k] = std::max(h[k], v);
      }
    }
    if (end - begin <= kLeafSize) return id;
    int split = 0;
    double spread = -1.0;
    for (int k = 0; k < dim_.get(); ++k) {
      if (h[k] - l[k] > spread) {
        spread = h[k] - l[k];
        split = k;
      }
    }
    if (spread <= 0.0) return id;  // all points identical: one leaf
    const int mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](int a, int b) {
                       const double va = points(a, split);
                       const double vb = points(b, split);
                       return va < vb || (va == vb && a < b);
                     });
    const int left = build(points, begin, mid);
    const int right = build(points, mid, end);
    nodes_[id].left = left;
    nodes_[id].right = right;
    return id;
  }

  int n_;
  Dim<D> dim_;
  std::vector<int> order_;
  std::vector<double> data_;
  std::vector<double> lo_;
  std::vector<double> hi_;
  std::vector<Node> nodes_;
  std::vector<int> leaf_of_;  ///< leaf of each tree position
};

/// Squared distance between the bounding boxes of node a of tree ta and node b of tree tb.
template <int D>
double boxBoxDistance2(const KdTree<D>& ta, int a, const KdTree<D>& tb, int b) {
  const double* la = ta.lo(a);
  const double* ha = ta.hi(a);
  const double* lb = tb.lo(b);
  const double* hb = tb.hi(b);
  double s = 0.0;
  for (int k = 0; k < ta.dim(); ++k) {
    const double e = std::max(std::max(la[k] - hb[k], lb[k] - ha[k]), 0.0);
    s += e * e;
  }
  return s;
}

/// Union-find with path halving and union by size.
class UnionFind {
 public:
  explicit UnionFind(int n) : parent_(n), size_(n, 1) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int find(int x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  bool unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (size_[a] < size_[b] || (size_[a] == size_[b] && b < a)) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
    return true;
  }

 private:
  std::vector<int> parent_;
  std::vector<int> size_;
};

/// Edge key in the strict total order (d^2, lo, hi).
struct EdgeKey {
  double d2 = std::numeric_limits<double>::infinity();
  int lo = kNoPoint;
  int hi = kNoPoint;
  bool operator<(const EdgeKey& o) const {
    if (d2 != o.d2) return d2 < o.d2;
    if (lo != o.lo) return lo < o.lo;
    return hi < o.hi;
  }
};

/// Dual-tree Borůvka: every round finds, for each component, its shortest outgoing edge.
}  // namespace taskmap::detail::emst
