#pragma once
// Private to grasp_sim (culled_query.cpp, lean_query.cpp): the separating planes of a link shape
// in the object frame and the walk of Bullet's quantized tree in Bullet's own order.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <type_traits>
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
/// rejected subtree by its escape index), with our node test on inner nodes: leaves come in
/// Bullet's order. A leaf's box is not tested: `leaf(triangle)` must begin with a test on the
/// triangle that rejects whatever its box would (ShapePlanes::bound: the triangle lies in its
/// box, so every plane puts it at least as far). `leaf` returns false to stop; it may take the
/// leaf's node index as a second argument. (Bullet's
/// accessors are non-const; nothing is changed.)
template <class Accept, class Leaf>
void walkInBulletOrder(const CollisionScene::Data& d, const Accept& accept, const Leaf& leaf) {
  const auto& nodes = d.mesh_shape->getOptimizedBvh()->getQuantizedNodeArray();
  if (nodes.size() == 0) return;
  const int end = nodes[0].isLeafNode() ? 1 : nodes[0].getEscapeIndex();
  int cur = 0;
  while (cur < end) {
    const btQuantizedBvhNode& n = nodes[cur];
    if (n.isLeafNode()) {
      if constexpr (std::is_invocable_v<Leaf, int, int>) {
        if (!leaf(n.getTriangleIndex(), cur)) return;
      } else {
        if (!leaf(n.getTriangleIndex())) return;
      }
      ++cur;
    } else {
      const auto& box = d.node_boxes[static_cast<std::size_t>(cur)];
      cur += accept(box[0], box[1]) ? 1 : n.getEscapeIndex();
    }
  }
}

/// The separating planes of one shape in the object frame: max over the shape of n[i] . x is
/// h[i]; a point set beyond one plane by more than `cut` is farther than the threshold. Planes
/// are tested kPlaneBlock at a time (columns, vector arithmetic), stopping after the first block
/// that puts a bound above its limit; padding planes give -inf.
struct ShapePlanes {
  using Block = Eigen::Array<double, kPlaneBlock, 1>;
  static constexpr int kBoxPlanes = 6;
  using BoxBlock = Eigen::Array<double, kBoxPlanes, 1>;
  static_assert(kPlaneBlock >= kBoxPlanes, "a box's faces fill its first block");
  // Object-frame normals and offsets, ShapeEntry's layout (mutable: face blocks are placed on
  // their first read, placed()).
  mutable Eigen::ArrayXd nx, ny, nz, h;
  Eigen::ArrayXd ax, ay, az;             // |n| per component, node planes only
  mutable Eigen::ArrayXd fd0, fd1, fd2;  // faceGap: n . v_k of the last triangle, per corner
  mutable Eigen::ArrayXd fub[3];         // faceGap: per face block, its bound for corner k
  mutable Eigen::ArrayXd fmin;           // faceGap: per face block, the smallest of the three
  mutable std::vector<char> fread;       // faceGap: per face block, whether it was computed
  // Per face block, whether its planes are in the object frame yet: set() transforms the planes
  // before the faces, a face block is transformed when first read (placed()), with the same
  // arithmetic element by element (most questions never read most of a hull's faces: the base
  // link of a Robotiq 2F-85 has 1555).
  mutable std::vector<char> fplaced;
  const ShapeEntry* fe = nullptr;                     // the shape (its face blocks)
  Eigen::Matrix3d rot = Eigen::Matrix3d::Identity();  // shape frame -> object frame
  Eigen::Vector3d org = Eigen::Vector3d::Zero();
  // (The columns may be longer than count: entries from count on are stale.)
  int node_planes = 0;  // the first ones, tested on tree nodes
  int node_pair = -1;   // the block of node planes holding two planes then padding (or -1)
  int facet_begin = 0;  // the ones before, tested on triangles; hulls: the face planes after
  int count = 0;
  bool box = false;  // a box: planes [0, 6) its faces, the rest of the block padding
  double cut = 0.0;
  Eigen::Vector3d qlo, qhi;  // the shape's padded bounding box (Bullet's query box)
  // The plane that last culled a node / a triangle, tried first (neighbours in the tree are
  // mostly culled by the same plane). Only the order of the planes changes: a bound above its
  // limit is above it whichever plane shows it, and a bound at or below it is the full maximum.
  mutable int node_hint = 0, tri_hint = 0;
  // walkNearestFirst's stack (bound, node), kept with the planes (which callers keep per thread)
  // rather than in a thread_local of its own: one lookup of thread-local storage less per walk.
  mutable std::vector<std::pair<double, int>> walk_stack;

  void set(const ShapeEntry& e, const Eigen::Isometry3d& ts, const btVector3& amin,
           const btVector3& amax, double threshold) {
    const Eigen::Matrix3d& r = ts.linear();
    const Eigen::Vector3d c = ts.translation();
    fe = &e;
    rot = r;
    org = c;
    for (auto& u : fub)
      if (u.size() < e.bx.size()) u.resize(e.bx.size());
    if (fmin.size() < e.bx.size()) fmin.resize(e.bx.size());
    count = static_cast<int>(e.pr.size());
    node_planes = e.node_planes;
    node_pair = -1;
    for (int b = 0; b < node_planes; b += kPlaneBlock)
      if (std::isinf(e.pr[b + 2]) && !std::isinf(e.pr[b + 1])) node_pair = b;
    facet_begin = e.facet_begin;
    box = e.is_box && count == kPlaneBlock;
    // The columns only grow (shapes of one hand alternate between sizes); [0, count) is used.
    if (nx.size() < count) {
      for (Eigen::ArrayXd* a : {&nx, &ny, &nz, &h, &ax, &ay, &az, &fd0, &fd1, &fd2})
        a->resize(count);
    }
    place(0, facet_begin);
    fplaced.assign(static_cast<std::size_t>((count - facet_begin) / kPlaneBlock), 0);
    ax.head(node_planes) = nx.head(node_planes).abs();
    ay.head(node_planes) = ny.head(node_planes).abs();
    az.head(node_planes) = nz.head(node_planes).abs();
    node_hint = std::min(node_hint, node_planes - 1);
    tri_hint = std::min(tri_hint, count - 1);
    cut = threshold + kCullSlack;
    qlo = eig(amin) - Eigen::Vector3d::Constant(threshold);
    qhi = eig(amax) + Eigen::Vector3d::Constant(threshold);
  }
  /// Every plane in the object frame now (tests that read the columns directly).
  void placeAll() const {
    for (std::size_t j = 0; j < fplaced.size(); ++j) placed(static_cast<int>(j));
  }
  /// Lower bound of the distance of a tree node's box from the shape (planes only); +inf
  /// outside the query box; stops early once above `limit`.
  double nodeBound(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double limit) const {
    if ((lo.array() > qhi.array()).any() || (hi.array() < qlo.array()).any())
      return std::numeric_limits<double>::infinity();
    const Eigen::Vector3d m = 0.5 * (lo + hi), e = 0.5 * (hi - lo);
    const int k = node_hint;
    const double g = nx[k] * m.x() + ny[k] * m.y() + nz[k] * m.z() -
                     (ax[k] * e.x() + ay[k] * e.y() + az[k] * e.z()) - h[k];
    if (g > limit) return g;
    double lb = -std::numeric_limits<double>::infinity();
    if (box) {  // the six faces alone (the padding planes never raise the bound)
      const BoxBlock gb = nx.head<kBoxPlanes>() * m.x() + ny.head<kBoxPlanes>() * m.y() +
                          nz.head<kBoxPlanes>() * m.z() -
                          (ax.head<kBoxPlanes>() * e.x() + ay.head<kBoxPlanes>() * e.y() +
                           az.head<kBoxPlanes>() * e.z()) -
                          h.head<kBoxPlanes>();
      raise(gb, 0, limit, &lb, &node_hint);
      return lb;
    }
    for (int b = 0; b < node_planes; b += kPlaneBlock) {
      if (b == node_pair) {  // two planes and padding: the two alone (padding never raises it)
        if (raise(nodeGaps<2>(b, m, e), b, limit, &lb, &node_hint)) break;
        continue;
      }
      if (raise(nodeGaps<kPlaneBlock>(b, m, e), b, limit, &lb, &node_hint)) break;
    }
    return lb;
  }
  bool node(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
    return nodeBound(lo, hi, cut) <= cut;
  }
  /// Lower bound of the triangle's distance from the planes; > limit when culled (stops early).
  double bound(const std::array<Eigen::Vector3d, 3>& v, double limit, bool tight = false) const {
    const Eigen::Vector3d tlo = v[0].cwiseMin(v[1]).cwiseMin(v[2]);
    const Eigen::Vector3d thi = v[0].cwiseMax(v[1]).cwiseMax(v[2]);
    if ((tlo.array() > qhi.array()).any() || (thi.array() < qlo.array()).any())
      return std::numeric_limits<double>::infinity();
    const int k = tri_hint;
    placedPlane(k);  // a face plane after a tight bound
    auto along = [&](int i, const Eigen::Vector3d& p) {
      return nx[i] * p.x() + ny[i] * p.y() + nz[i] * p.z();
    };
    const double g = std::min({along(k, v[0]), along(k, v[1]), along(k, v[2])}) - h[k];
    if (g > limit) return g;
    double lb = -std::numeric_limits<double>::infinity();
    if (box) {
      const BoxBlock gb =
          boxAlong(v[0]).min(boxAlong(v[1])).min(boxAlong(v[2])) - h.head<kBoxPlanes>();
      raise(gb, 0, limit, &lb, &tri_hint);
      return lb;
    }
    const int end = tight ? count : facet_begin;
    for (int b = 0; b < end; b += kPlaneBlock) {
      placedPlane(b);
      const Block gb = alongBlock(b, v[0]).min(alongBlock(b, v[1])).min(alongBlock(b, v[2])) -
                       h.segment<kPlaneBlock>(b);
      if (raise(gb, b, limit, &lb, &tri_hint)) break;
    }
    return lb;
  }
  double bound(const std::array<Eigen::Vector3d, 3>& v) const { return bound(v, cut); }
  /// The largest gap of triangle `v` over a hull's face planes [facet_begin, count),
  /// max_i (min_k n_i . v_k - h_i), and in *face a plane reaching it (the first in the hull
  /// computation's order among equals); some value above `limit` (and *face -1) as soon as a
  /// block of faces puts the triangle beyond it. Blocks are read from the one with the largest
  /// upper bound (ShapeEntry::bx...: for each corner axis . p + |p| chord - bmin, p the corner in
  /// the shape frame; the smallest of the three) on, and a block whose bound is below the gap
  /// found by more than kCullSlack (far above the rounding) is skipped: it holds no face as high.
  /// Keeps every n_i . v_k it computed and the bounds: faceContact and insideFaces of the same
  /// triangle read them (the same arithmetic as computing them again, so the same numbers).
  double faceGap(const std::array<Eigen::Vector3d, 3>& v, double limit, int* face) const {
    const int nb = (count - facet_begin) / kPlaneBlock;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = rot.transpose() * (v[static_cast<std::size_t>(k)] - org);
      fub[k].head(nb) =
          fe->bx * p.x() + fe->by * p.y() + fe->bz * p.z() + p.norm() * fe->bchord - fe->bmin;
    }
    fread.assign(static_cast<std::size_t>(nb), 0);
    fmin.head(nb) = fub[0].head(nb).min(fub[1].head(nb)).min(fub[2].head(nb));
    const auto ub = fmin.head(nb);
    const int top = firstMax(ub);
    double g = -std::numeric_limits<double>::infinity();
    int rank = std::numeric_limits<int>::max();
    *face = -1;
    for (int j = -1; j < nb; ++j) {
      const int blk = j < 0 ? static_cast<int>(top) : j;
      if (j == top || (j >= 0 && ub[j] + kCullSlack < g)) continue;
      const int b = facet_begin + blk * kPlaneBlock;
      placed(blk);
      const Block a0 = alongBlock(b, v[0]), a1 = alongBlock(b, v[1]), a2 = alongBlock(b, v[2]);
      fd0.segment<kPlaneBlock>(b) = a0;
      fd1.segment<kPlaneBlock>(b) = a1;
      fd2.segment<kPlaneBlock>(b) = a2;
      fread[static_cast<std::size_t>(blk)] = 1;
      const Block gb = a0.min(a1).min(a2) - h.segment<kPlaneBlock>(b);
      const double m = gb.maxCoeff();
      if (m >= g)
        for (int i = 0; i < kPlaneBlock; ++i) {
          const int r = fe->face_rank[static_cast<std::size_t>(b + i - facet_begin)];
          if (gb(i) > g || (gb(i) == g && r < rank)) {
            g = gb(i);
            rank = r;
            *face = b + i;
          }
        }
      if (g > limit) {
        *face = -1;
        return g;
      }
    }
    return g;
  }
  /// After faceGap(v, ...) returned g <= its limit with face F: a hull's penetration of
  /// triangle `v` from its face planes, when they prove it: g < -min_depth, p the triangle's
  /// corners deepest below F (within 1e-9 m of each other); if every such corner lies at least
  /// -g inside every face, the ball of radius -g about it lies in the hull, so no translation
  /// shorter than -g separates the pair, and moving -g along F's normal does: the penetration
  /// depth is -g, along F's normal, witness the corners' mean. False where that does not hold
  /// (near the hull's edges): EPA decides there. A block faceGap skipped is read only where its
  /// bound for the corner does not put every face of it more than kCullSlack below g.
  bool faceContact(const std::array<Eigen::Vector3d, 3>& v, double g, int face, double min_depth,
                   double* depth, Eigen::Vector3d* normal, Eigen::Vector3d* point) const {
    if (face < 0 || !(g < -min_depth)) return false;
    const Eigen::Vector3d n(nx[face], ny[face], nz[face]);
    const double lo = std::min({n.dot(v[0]), n.dot(v[1]), n.dot(v[2])});
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int tied = 0;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& p = v[static_cast<std::size_t>(k)];
      if (n.dot(p) > lo + 1e-9) continue;
      const double inside = faceClearance(p, k, g);  // distance to the boundary (where needed)
      if (inside < -g - 1e-12) return false;
      sum += p;
      ++tied;
    }
    *depth = -g;
    *normal = -n;
    *point = sum / static_cast<double>(tied);
    return true;
  }
  /// After faceGap(v, ...) computed every block up to its limit: inside(v[corner], facet_begin),
  /// from its products, reading a skipped block only where its bound for the corner does not
  /// put it more than kCullSlack below -kInsideSlack.
  bool insideFaces(const std::array<Eigen::Vector3d, 3>& v, int corner) const {
    const Eigen::ArrayXd& a = corner == 0 ? fd0 : corner == 1 ? fd1 : fd2;
    const int nb = (count - facet_begin) / kPlaneBlock;
    for (int j = 0; j < nb; ++j) {
      const int b = facet_begin + j * kPlaneBlock;
      if (fread[static_cast<std::size_t>(j)]) {
        if ((a.segment<kPlaneBlock>(b) - h.segment<kPlaneBlock>(b)).maxCoeff() >= -kInsideSlack)
          return false;
      } else if (fub[corner][j] + kCullSlack >= -kInsideSlack && placed(j) &&
                 (alongBlock(b, v[static_cast<std::size_t>(corner)]) - h.segment<kPlaneBlock>(b))
                         .maxCoeff() >= -kInsideSlack) {
        return false;
      }
    }
    return true;
  }
  /// True when `p` lies deeper than kInsideSlack inside every plane from `first` on.
  bool inside(const Eigen::Vector3d& p, int first) const {
    for (int b = first; b < count; b += kPlaneBlock)
      if (placedPlane(b) &&
          (alongBlock(b, p) - h.segment<kPlaneBlock>(b)).maxCoeff() >= -kInsideSlack)
        return false;
    return true;
  }

 private:
  /// n . m - |n| . e - h for the node planes [b, b + N) (a node box of centre m, half extent e).
  template <int N>
  Eigen::Array<double, N, 1> nodeGaps(int b, const Eigen::Vector3d& m,
                                      const Eigen::Vector3d& e) const {
    return nx.segment<N>(b) * m.x() + ny.segment<N>(b) * m.y() + nz.segment<N>(b) * m.z() -
           (ax.segment<N>(b) * e.x() + ay.segment<N>(b) * e.y() + az.segment<N>(b) * e.z()) -
           h.segment<N>(b);
  }
  /// Transforms the planes [b, end) to the object frame (rot, org).
  void place(int b, int end) const {
    const int n = end - b;
    if (n <= 0) return;
    const ShapeEntry& e = *fe;
    const Eigen::Matrix3d& r = rot;
    Eigen::ArrayXd &mx = nx, &my = ny, &mz = nz, &mh = h;
    mx.segment(b, n) =
        r(0, 0) * e.px.segment(b, n) + r(0, 1) * e.py.segment(b, n) + r(0, 2) * e.pz.segment(b, n);
    my.segment(b, n) =
        r(1, 0) * e.px.segment(b, n) + r(1, 1) * e.py.segment(b, n) + r(1, 2) * e.pz.segment(b, n);
    mz.segment(b, n) =
        r(2, 0) * e.px.segment(b, n) + r(2, 1) * e.py.segment(b, n) + r(2, 2) * e.pz.segment(b, n);
    mh.segment(b, n) =
        e.pr.segment(b, n) +
        (mx.segment(b, n) * org.x() + my.segment(b, n) * org.y() + mz.segment(b, n) * org.z());
  }
  /// Face block j in the object frame (transformed on its first read); true.
  bool placed(int j) const {
    auto& f = fplaced[static_cast<std::size_t>(j)];
    if (!f) {
      const int b = facet_begin + j * kPlaneBlock;
      place(b, b + kPlaneBlock);
      f = 1;
    }
    return true;
  }
  /// The block of planes from b in the object frame; true.
  bool placedPlane(int b) const {
    return b < facet_begin || placed((b - facet_begin) / kPlaneBlock);
  }
  /// The first index of the largest entry (as Eigen's maxCoeff(&index); no NaN here): the
  /// largest by a vector max, then the first entry equal to it.
  template <class A>
  static int firstMax(const A& a) {
    const double m = a.maxCoeff();
    int i = 0;
    while (i + 1 < a.size() && !(a[i] == m)) ++i;
    return i;
  }
  /// min over the face planes of h_i - n_i . p, p = corner k of faceGap's triangle, except
  /// blocks faceGap skipped whose bound for p puts every face more than kCullSlack below g
  /// (those faces' h_i - n_i . p exceed -g: they cannot decide faceContact's test).
  double faceClearance(const Eigen::Vector3d& p, int k, double g) const {
    const Eigen::ArrayXd& a = k == 0 ? fd0 : k == 1 ? fd1 : fd2;
    const int nb = (count - facet_begin) / kPlaneBlock;
    double inside = std::numeric_limits<double>::infinity();
    for (int j = 0; j < nb; ++j) {
      const int b = facet_begin + j * kPlaneBlock;
      if (fread[static_cast<std::size_t>(j)])
        inside =
            std::min(inside, (h.segment<kPlaneBlock>(b) - a.segment<kPlaneBlock>(b)).minCoeff());
      else if (!(fub[k][j] + kCullSlack < g) && placed(j))
        inside = std::min(inside, (h.segment<kPlaneBlock>(b) - alongBlock(b, p)).minCoeff());
    }
    return inside;
  }
  /// n . p for the planes [b, b + kPlaneBlock).
  Block alongBlock(int b, const Eigen::Vector3d& p) const {
    return nx.segment<kPlaneBlock>(b) * p.x() + ny.segment<kPlaneBlock>(b) * p.y() +
           nz.segment<kPlaneBlock>(b) * p.z();
  }
  /// n . p for a box's six face planes.
  BoxBlock boxAlong(const Eigen::Vector3d& p) const {
    return nx.head<kBoxPlanes>() * p.x() + ny.head<kBoxPlanes>() * p.y() +
           nz.head<kBoxPlanes>() * p.z();
  }
  /// Raises *lb to the largest gap of block gb (the planes from b); true when it is now above
  /// `limit`, with *hint naming a plane of the block that is above it.
  template <class B>
  static bool raise(const B& gb, int b, double limit, double* lb, int* hint) {
    *lb = std::max(*lb, gb.maxCoeff());
    if (!(*lb > limit)) return false;
    *hint = b + firstAbove(gb, limit);
    return true;
  }
  /// Index in `gb` of the first gap above `limit` (one exists).
  template <class B>
  static int firstAbove(const B& gb, double limit) {
    int i = 0;
    while (i + 1 < gb.size() && !(gb(i) > limit)) ++i;
    return i;
  }
};

/// Admits the tree nodes that may hold a triangle whose outward normal n satisfies
/// n . b > cos(phi) (b unit): a node whose normal cone (CollisionScene::Data::node_cones) lies
/// farther than phi + 1e-6 rad from b holds none.
struct NormalFilter {
  Eigen::Vector3d b = Eigen::Vector3d::UnitZ();
  double phi = 0.0;  ///< radians, in [0, pi]
  double cos_phi = 1.0, sin_phi = 0.0;
  NormalFilter(const Eigen::Vector3d& dir, double cos_bound)
      : b(dir), phi(std::acos(cos_bound) + 1e-6), cos_phi(std::cos(phi)), sin_phi(std::sin(phi)) {}
  bool admits(const CollisionScene::Data::NormalCone& c) const {
    if (c.half + phi >= kPi) return true;
    return c.axis.dot(b) > c.cos_half * cos_phi - c.sin_half * sin_phi;  // cos(half + phi)
  }
};

/// Depth-first branch and bound over Bullet's tree with the planes `pl` as bound, the nearer
/// child first: a node whose bound exceeds pl.cut or limit() + kCullSlack is skipped (a leaf's
/// bound is its triangle's, ShapePlanes::bound); leaf(tri, bound, node) gets the triangles of
/// the others that accept(tri) admits (node: the leaf's index, which orders leaves as Bullet's
/// walk does) until stop() holds; with `normals`, inner nodes it does not admit are skipped (it
/// must admit every triangle accept admits). limit() must never grow: a node above it when its
/// parent is opened is dropped then (its bound computed only up to it), as it would be when
/// popped.
template <class Limit, class Stop, class Accept, class Leaf>
void walkNearestFirst(const CollisionScene::Data& d, const ShapePlanes& pl, const Limit& limit,
                      const Stop& stop, const Accept& accept, const NormalFilter* normals,
                      const Leaf& leaf) {
  const auto& nodes = d.mesh_shape->getOptimizedBvh()->getQuantizedNodeArray();
  if (nodes.size() == 0) return;
  // The bound of node i if it is at most `cut`, else some value above `cut`.
  auto bound = [&](int i, double cut) {
    const btQuantizedBvhNode& n = nodes[i];
    if (n.isLeafNode()) {
      const int tri = n.getTriangleIndex();
      if (!accept(tri)) return std::numeric_limits<double>::infinity();
      return pl.bound(d.corners[static_cast<std::size_t>(tri)], cut);
    }
    if (normals && !normals->admits(d.node_cones[static_cast<std::size_t>(i)]))
      return std::numeric_limits<double>::infinity();
    const auto& box = d.node_boxes[static_cast<std::size_t>(i)];
    return pl.nodeBound(box[0], box[1], cut);
  };
  std::vector<std::pair<double, int>>& stack = pl.walk_stack;  // (bound, node)
  stack.clear();
  stack.emplace_back(bound(0, pl.cut), 0);
  while (!stack.empty() && !stop()) {
    const auto [lb, i] = stack.back();
    stack.pop_back();
    const double cut = std::min(pl.cut, limit() + kCullSlack);
    if (lb > cut) continue;
    const btQuantizedBvhNode& n = nodes[i];
    if (n.isLeafNode()) {
      leaf(n.getTriangleIndex(), lb, i);
      continue;
    }
    const int left = i + 1;
    const int right = left + (nodes[left].isLeafNode() ? 1 : nodes[left].getEscapeIndex());
    std::pair<double, int> a{bound(left, cut), left}, b{bound(right, cut), right};
    if (a.first < b.first) std::swap(a, b);  // push the farther first, pop the nearer first
    if (a.first <= cut) stack.push_back(a);
    if (b.first <= cut) stack.push_back(b);
  }
}

/// walkNearestFirst over every triangle.
template <class Limit, class Stop, class Leaf>
void walkNearestFirst(const CollisionScene::Data& d, const ShapePlanes& pl, const Limit& limit,
                      const Stop& stop, const Leaf& leaf) {
  walkNearestFirst(
      d, pl, limit, stop, [](int) { return true; }, nullptr, leaf);
}

/// Runs `q` on triangle `tri` (corners from d.corners).
inline void runTriangle(const CollisionScene::Data& d, int tri, TriangleQuery* q) {
  const auto& v = d.corners[static_cast<std::size_t>(tri)];
  btVector3 corners[3] = {bt(v[0]), bt(v[1]), bt(v[2])};
  q->processTriangle(corners, 0, tri);
}

}  // namespace taskmap
