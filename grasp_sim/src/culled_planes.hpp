#pragma once
// Private to grasp_sim (culled_query.cpp, lean_query.cpp): the separating planes of a link shape
// in the object frame and the walk of Bullet's quantized tree in Bullet's own order.

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "collision_data.hpp"

namespace taskmap {

/// A triangle is culled when a plane puts it farther than threshold + kCullSlack, metres (GJK
/// in double precision is accurate to ~1e-12 relative; this leaves three orders of margin).
constexpr double kCullSlack = 1e-9;
/// A triangle corner deeper than this inside a hull's face planes proves an overlap, metres.
constexpr double kInsideSlack = 1e-6;

/// Walks Bullet's quantized tree as its stackless walk does (node array order, skipping a
/// rejected subtree by its escape index), with our node test: leaves come in Bullet's order.
/// `leaf(triangle)` returns false to stop. (Bullet's accessors are non-const; nothing is changed.)
template <class Accept, class Leaf>
void walkInBulletOrder(btQuantizedBvh& bvh, const Accept& accept, const Leaf& leaf) {
  const auto& nodes = bvh.getQuantizedNodeArray();
  if (nodes.size() == 0) return;
  const int end = nodes[0].isLeafNode() ? 1 : nodes[0].getEscapeIndex();
  int cur = 0;
  while (cur < end) {
    const btQuantizedBvhNode& n = nodes[cur];
    const bool pass = accept(eig(bvh.unQuantize(n.m_quantizedAabbMin)),
                             eig(bvh.unQuantize(n.m_quantizedAabbMax)));
    if (n.isLeafNode()) {
      if (pass && !leaf(n.getTriangleIndex())) return;
      ++cur;
    } else {
      cur += pass ? 1 : n.getEscapeIndex();
    }
  }
}

/// The separating planes of one shape in the object frame: max over the shape of wn[i] . x is
/// wh[i]; a point set beyond one plane by more than `cut` is farther than the threshold.
struct ShapePlanes {
  std::vector<Eigen::Vector3d> wn;
  std::vector<double> wh;
  std::size_t node_planes = 0;  // the first ones, tested on tree nodes
  std::size_t facet_begin = 0;  // hulls: the face planes from here on
  double cut = 0.0;
  Eigen::Vector3d qlo, qhi;  // the shape's padded bounding box (Bullet's query box)
  // The plane that last culled a node / a triangle, tried first (neighbours in the tree are
  // mostly culled by the same plane). Only the order of the planes changes: a bound above its
  // limit is above it whichever plane shows it, and a bound at or below it is the full maximum.
  mutable std::size_t node_hint = 0, tri_hint = 0;

  void set(const ShapeEntry& e, const Eigen::Isometry3d& ts, const btVector3& amin,
           const btVector3& amax, double threshold) {
    const Eigen::Vector3d c = ts.translation();
    wn.resize(e.axes.size());
    wh.resize(e.axes.size());
    for (std::size_t i = 0; i < e.axes.size(); ++i) {
      wn[i] = ts.linear() * e.axes[i];
      wh[i] = e.reach[i] + wn[i].dot(c);
    }
    node_planes = static_cast<std::size_t>(e.node_planes);
    facet_begin = static_cast<std::size_t>(e.facet_begin);
    cut = threshold + kCullSlack;
    qlo = eig(amin) - Eigen::Vector3d::Constant(threshold);
    qhi = eig(amax) + Eigen::Vector3d::Constant(threshold);
  }
  /// Lower bound of the distance of a tree node's box from the shape (planes only); +inf
  /// outside the query box; stops early once above `limit`.
  double nodeBound(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double limit) const {
    if ((lo.array() > qhi.array()).any() || (hi.array() < qlo.array()).any())
      return std::numeric_limits<double>::infinity();
    const Eigen::Vector3d mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
    auto gap = [&](std::size_t i) { return wn[i].dot(mid) - wn[i].cwiseAbs().dot(half) - wh[i]; };
    if (node_hint < node_planes) {
      const double g = gap(node_hint);
      if (g > limit) return g;
    }
    double lb = -std::numeric_limits<double>::infinity();
    std::size_t i = 0;
    for (; i < node_planes && lb <= limit; ++i) lb = std::max(lb, gap(i));
    if (lb > limit) node_hint = i - 1;
    return lb;
  }
  bool node(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
    return nodeBound(lo, hi, cut) <= cut;
  }
  /// Lower bound of the triangle's distance from the planes; > limit when culled (stops early).
  double bound(const std::array<Eigen::Vector3d, 3>& v, double limit) const {
    const Eigen::Vector3d tlo = v[0].cwiseMin(v[1]).cwiseMin(v[2]);
    const Eigen::Vector3d thi = v[0].cwiseMax(v[1]).cwiseMax(v[2]);
    if ((tlo.array() > qhi.array()).any() || (thi.array() < qlo.array()).any())
      return std::numeric_limits<double>::infinity();
    auto gap = [&](std::size_t i) {
      return std::min({wn[i].dot(v[0]), wn[i].dot(v[1]), wn[i].dot(v[2])}) - wh[i];
    };
    if (tri_hint < wn.size()) {
      const double g = gap(tri_hint);
      if (g > limit) return g;
    }
    double lb = -std::numeric_limits<double>::infinity();
    std::size_t i = 0;
    for (; i < wn.size() && lb <= limit; ++i) lb = std::max(lb, gap(i));
    if (lb > limit) tri_hint = i - 1;
    return lb;
  }
  double bound(const std::array<Eigen::Vector3d, 3>& v) const { return bound(v, cut); }
  /// True when `p` lies deeper than kInsideSlack inside every plane from `first` on.
  bool inside(const Eigen::Vector3d& p, std::size_t first) const {
    for (std::size_t i = first; i < wn.size(); ++i)
      if (wn[i].dot(p) - wh[i] >= -kInsideSlack) return false;
    return true;
  }
};

/// Depth-first branch and bound over Bullet's tree with the planes `pl` as bound, the nearer
/// child first: a node whose bound exceeds pl.cut or limit() + kCullSlack is skipped; leaf(tri)
/// gets the triangles of the others (it applies its own triangle tests) until stop() holds.
template <class Limit, class Stop, class Leaf>
void walkNearestFirst(const CollisionScene::Data& d, const ShapePlanes& pl, const Limit& limit,
                      const Stop& stop, const Leaf& leaf) {
  btOptimizedBvh& bvh = *d.mesh_shape->getOptimizedBvh();
  const auto& nodes = bvh.getQuantizedNodeArray();
  if (nodes.size() == 0) return;
  auto bound = [&](int i) {
    const btQuantizedBvhNode& n = nodes[i];
    return pl.nodeBound(eig(bvh.unQuantize(n.m_quantizedAabbMin)),
                        eig(bvh.unQuantize(n.m_quantizedAabbMax)), pl.cut);
  };
  thread_local std::vector<std::pair<double, int>> stack;  // (bound, node)
  stack.clear();
  stack.emplace_back(bound(0), 0);
  while (!stack.empty() && !stop()) {
    const auto [lb, i] = stack.back();
    stack.pop_back();
    if (lb > pl.cut || lb > limit() + kCullSlack) continue;
    const btQuantizedBvhNode& n = nodes[i];
    if (n.isLeafNode()) {
      leaf(n.getTriangleIndex());
      continue;
    }
    const int left = i + 1;
    const int right = left + (nodes[left].isLeafNode() ? 1 : nodes[left].getEscapeIndex());
    std::pair<double, int> a{bound(left), left}, b{bound(right), right};
    if (a.first < b.first) std::swap(a, b);  // push the farther first, pop the nearer first
    stack.push_back(a);
    stack.push_back(b);
  }
}

/// Runs `q` on triangle `tri` (corners from d.corners).
inline void runTriangle(const CollisionScene::Data& d, int tri, TriangleQuery* q) {
  const auto& v = d.corners[static_cast<std::size_t>(tri)];
  btVector3 corners[3] = {bt(v[0]), bt(v[1]), bt(v[2])};
  q->processTriangle(corners, 0, tri);
}

}  // namespace taskmap
