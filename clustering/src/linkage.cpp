// Dendrograms in scipy's linkage format: single linkage from the Euclidean MST (emst.cpp),
// average and complete linkage by the nearest-neighbour chain, and scipy's relabelling.

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "linkage_internal.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {

namespace {

/// Largest point count for the O(n^2)-memory methods (a condensed matrix of 2e4 points
/// takes 1.6 GB).
constexpr int kMaxChainPoints = kMaxPairwiseLinkagePoints;

}  // namespace

const char* toString(Linkage method) {
  switch (method) {
    case Linkage::kSingle:
      return "single";
    case Linkage::kAverage:
      return "average";
    case Linkage::kComplete:
      return "complete";
  }
  return "unknown";
}

Linkage linkageFromString(const std::string& name) {
  if (name == "single") return Linkage::kSingle;
  if (name == "average") return Linkage::kAverage;
  if (name == "complete") return Linkage::kComplete;
  throw Error("unknown linkage method '" + name + "': use single, average or complete");
}

namespace detail {

std::vector<PointMerge> nearestNeighbourChain(const PointMatrix& points, Linkage method) {
  const std::int64_t n = points.rows();
  const int dim = static_cast<int>(points.cols());
  assert(n >= 2);
  // Condensed distance matrix, scipy's layout: (i, j), i < j at n*i - i*(i+1)/2 + j - i - 1.
  auto index = [n](std::int64_t i, std::int64_t j) {
    if (i > j) std::swap(i, j);
    return n * i - i * (i + 1) / 2 + j - i - 1;
  };
  std::vector<double> dist(static_cast<std::size_t>(n * (n - 1) / 2));
  for (std::int64_t i = 0; i < n; ++i) {
    const double* a = points.row(i).data();
    for (std::int64_t j = i + 1; j < n; ++j) {
      const double* b = points.row(j).data();
      double s = 0.0;
      for (int k = 0; k < dim; ++k) {
        const double e = a[k] - b[k];
        s += e * e;
      }
      dist[static_cast<std::size_t>(index(i, j))] = std::sqrt(s);
    }
  }
  std::vector<std::int64_t> size(static_cast<std::size_t>(n), 1);
  std::vector<std::int64_t> chain(static_cast<std::size_t>(n));
  std::int64_t chain_length = 0;
  std::vector<PointMerge> merges;
  merges.reserve(static_cast<std::size_t>(n - 1));
  for (std::int64_t k = 0; k < n - 1; ++k) {
    if (chain_length == 0) {
      for (std::int64_t i = 0; i < n; ++i) {
        if (size[i] > 0) {
          chain[0] = i;
          break;
        }
      }
      chain_length = 1;
    }
    std::int64_t x = 0;
    std::int64_t y = 0;
    double current_min = 0.0;
    while (true) {
      x = chain[chain_length - 1];
      if (chain_length > 1) {
        y = chain[chain_length - 2];
        current_min = dist[static_cast<std::size_t>(index(x, y))];
      } else {
        current_min = std::numeric_limits<double>::infinity();
      }
      for (std::int64_t i = 0; i < n; ++i) {
        if (size[i] == 0 || i == x) continue;
        const double d = dist[static_cast<std::size_t>(index(x, i))];
        if (d < current_min) {
          current_min = d;
          y = i;
        }
      }
      if (chain_length > 1 && y == chain[chain_length - 2]) break;
      chain[chain_length++] = y;
    }
    chain_length -= 2;
    if (x > y) std::swap(x, y);
    const std::int64_t nx = size[x];
    const std::int64_t ny = size[y];
    merges.push_back(PointMerge{static_cast<int>(x), static_cast<int>(y), current_min});
    size[x] = 0;
    size[y] = nx + ny;
    // Lance-Williams update; the merged cluster lives at y.
    for (std::int64_t i = 0; i < n; ++i) {
      if (size[i] == 0 || i == y) continue;
      double& d_iy = dist[static_cast<std::size_t>(index(i, y))];
      const double d_ix = dist[static_cast<std::size_t>(index(i, x))];
      if (method == Linkage::kComplete) {
        d_iy = std::max(d_ix, d_iy);
      } else {
        d_iy = (static_cast<double>(nx) * d_ix + static_cast<double>(ny) * d_iy) /
               static_cast<double>(nx + ny);
      }
    }
  }
  return merges;
}

LinkageMatrix labelMerges(std::vector<PointMerge> merges) {
  const int n = static_cast<int>(merges.size()) + 1;
  std::stable_sort(merges.begin(), merges.end(),
                   [](const PointMerge& a, const PointMerge& b) { return a.d < b.d; });
  // Union-find over the 2n - 1 dendrogram nodes; a root is the cluster's id (scipy's label).
  std::vector<int> parent(2 * static_cast<std::size_t>(n) - 1);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<double> size(parent.size(), 1.0);
  auto find = [&parent](int x) {
    int root = x;
    while (parent[root] != root) root = parent[root];
    while (parent[x] != root) {
      const int next = parent[x];
      parent[x] = root;
      x = next;
    }
    return root;
  };
  LinkageMatrix z(n - 1, 4);
  for (int k = 0; k < n - 1; ++k) {
    int a = find(merges[k].a);
    int b = find(merges[k].b);
    assert(a != b);
    if (a > b) std::swap(a, b);
    const int id = n + k;
    parent[a] = id;
    parent[b] = id;
    size[id] = size[a] + size[b];
    z(k, 0) = a;
    z(k, 1) = b;
    z(k, 2) = merges[k].d;
    z(k, 3) = size[id];
  }
  return z;
}

void validateLinkage(const LinkageMatrix& linkage, const char* what) {
  const std::int64_t rows = linkage.rows();
  const std::int64_t n = rows + 1;
  std::vector<char> used(static_cast<std::size_t>(2 * n - 1), 0);
  std::vector<double> size(static_cast<std::size_t>(2 * n - 1), 1.0);
  double previous = 0.0;
  for (std::int64_t k = 0; k < rows; ++k) {
    const std::string row = std::string(what) + ": linkage row " + std::to_string(k);
    for (int c = 0; c < 4; ++c) {
      if (!std::isfinite(linkage(k, c))) throw Error(row + " has a non-finite value");
    }
    const double d = linkage(k, 2);
    if (d < 0.0) throw Error(row + " has a negative distance");
    if (d < previous) throw Error(row + " has a smaller distance than the row before");
    previous = d;
    double child_size = 0.0;
    for (int c = 0; c < 2; ++c) {
      const double v = linkage(k, c);
      if (v != std::floor(v) || v < 0.0 || v >= static_cast<double>(n + k)) {
        throw Error(row + " refers to cluster " + std::to_string(v) +
                    ", which does not exist yet (ids must be below " + std::to_string(n + k) + ")");
      }
      const auto id = static_cast<std::size_t>(v);
      if (used[id]) throw Error(row + " merges cluster " + std::to_string(id) + " a second time");
      used[id] = 1;
      child_size += size[id];
    }
    if (linkage(k, 3) != child_size) {
      throw Error(row + " has size " + std::to_string(linkage(k, 3)) + ", expected " +
                  std::to_string(child_size));
    }
    size[static_cast<std::size_t>(n + k)] = child_size;
  }
}

}  // namespace detail

LinkageMatrix computeLinkage(const PointMatrix& points, Linkage method) {
  const auto n = points.rows();
  if (n < 2) {
    throw Error("computeLinkage needs at least 2 points, got " + std::to_string(n));
  }
  if (points.cols() < 1) throw Error("computeLinkage needs points with at least one coordinate");
  if (n > std::numeric_limits<int>::max() / 2) throw Error("computeLinkage: too many points");
  if (!points.allFinite()) {
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!points.row(i).allFinite()) {
        throw Error("computeLinkage: point " + std::to_string(i) + " has a non-finite coordinate");
      }
    }
  }
  if (method == Linkage::kSingle) return detail::labelMerges(detail::euclideanMst(points));
  if (n > kMaxChainPoints) {
    throw Error(std::string(toString(method)) + " linkage supports at most " +
                std::to_string(kMaxChainPoints) + " points (O(n^2) memory), got " +
                std::to_string(n) + ": use single linkage");
  }
  return detail::labelMerges(detail::nearestNeighbourChain(points, method));
}

namespace {

/// Labels 0..K-1 by first appearance after joining the first `applied` rows.
std::vector<int> labelsAfterRows(const LinkageMatrix& linkage, Eigen::Index applied) {
  const Eigen::Index n = linkage.rows() + 1;
  std::vector<int> parent(static_cast<std::size_t>(2 * n - 1));
  std::iota(parent.begin(), parent.end(), 0);
  for (Eigen::Index k = 0; k < applied; ++k) {
    const int id = static_cast<int>(n + k);
    parent[static_cast<std::size_t>(linkage(k, 0))] = id;
    parent[static_cast<std::size_t>(linkage(k, 1))] = id;
  }
  // Parents have larger ids than children: resolve roots from the top down.
  for (Eigen::Index v = 2 * n - 2; v >= 0; --v) {
    const int p = parent[static_cast<std::size_t>(v)];
    if (p != v) parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(p)];
  }
  std::vector<int> label_of_root(parent.size(), -1);
  std::vector<int> labels(static_cast<std::size_t>(n));
  int next = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    int& l = label_of_root[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    if (l < 0) l = next++;
    labels[static_cast<std::size_t>(i)] = l;
  }
  return labels;
}

}  // namespace

std::vector<int> cutAtDistance(const LinkageMatrix& linkage, double threshold) {
  detail::validateLinkage(linkage, "cutAtDistance");
  if (std::isnan(threshold)) throw Error("cutAtDistance: threshold is NaN");
  Eigen::Index applied = 0;
  while (applied < linkage.rows() && linkage(applied, 2) <= threshold) ++applied;
  return labelsAfterRows(linkage, applied);
}

std::vector<int> cutToCount(const LinkageMatrix& linkage, int k) {
  detail::validateLinkage(linkage, "cutToCount");
  const Eigen::Index n = linkage.rows() + 1;
  if (k < 1 || k > n) {
    throw Error("cutToCount: cluster count " + std::to_string(k) + " must be between 1 and " +
                std::to_string(n) + " (the number of points)");
  }
  return labelsAfterRows(linkage, n - k);
}

}  // namespace taskmap
