// Bounding-volume hierarchy for inside tests and distances (private to the meshes stage).
#include "mesh_bvh.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

namespace taskmap::detail {

Eigen::Vector3d closestOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) {
    // Degenerate triangle: closest of the three edges.
    auto seg = [&](const Eigen::Vector3d& s, const Eigen::Vector3d& e) -> Eigen::Vector3d {
      const Eigen::Vector3d se = e - s;
      const double len2 = se.squaredNorm();
      const double t = len2 > 0 ? std::clamp((p - s).dot(se) / len2, 0.0, 1.0) : 0.0;
      return s + t * se;
    };
    Eigen::Vector3d best = seg(a, b);
    for (const Eigen::Vector3d& q : {seg(b, c), seg(c, a)}) {
      if ((q - p).squaredNorm() < (best - p).squaredNorm()) best = q;
    }
    return best;
  }
  const double v = vb / denom, w = vc / denom;
  return a + ab * v + ac * w;
}

namespace {

constexpr int kLeafSize = 4;
/// Centroid bins per axis of a surface-area split.
constexpr int kSahBins = 16;
/// Levels split by surface area; deeper nodes split at the median (bounded depth).
constexpr int kMaxSahDepth = 32;

/// The bin of coordinate x among kSahBins over [lo, lo + extent] (extent > 0).
int binOf(double x, double lo, double extent) {
  const int b = static_cast<int>(kSahBins * ((x - lo) / extent));
  return std::clamp(b, 0, kSahBins - 1);
}
constexpr double kBaryTol = 1e-9;  ///< barycentric band around edges treated as ambiguous

double boxDistance2(const Eigen::Vector3d& p, const Eigen::Vector3d& lo,
                    const Eigen::Vector3d& hi) {
  const Eigen::Vector3d d = (lo - p).cwiseMax(p - hi).cwiseMax(0.0);
  return d.squaredNorm();
}

/// A ray's origin and componentwise inverse direction, for slab tests.
struct RaySlabs {
  RaySlabs(const Eigen::Vector3d& origin, const Eigen::Vector3d& d)
      : p(origin), inv(d.cwiseInverse()), finite(inv.allFinite()) {}
  Eigen::Vector3d p, inv;
  /// Every 1 / d component is finite: no slab product can be NaN (0 times infinity)
  bool finite;
};

/// True when the ray p + t d meets the box for some t in [0, t_end]; *t_enter receives the
/// entry parameter when given. With finite slabs, the same minima and maxima without the NaN
/// guard or branches.
bool rayHitsBox(const RaySlabs& r, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                double t_end = std::numeric_limits<double>::infinity(), double* t_enter = nullptr) {
  const Eigen::Vector3d& p = r.p;
  const Eigen::Vector3d& inv = r.inv;
  double t0 = 0, t1 = t_end;
  if (r.finite) {
    for (int k = 0; k < 3; ++k) {
      const double a = (lo[k] - p[k]) * inv[k], b = (hi[k] - p[k]) * inv[k];
      t0 = std::max(t0, std::min(a, b));
      t1 = std::min(t1, std::max(a, b));
    }
    if (t0 > t1) return false;
    if (t_enter != nullptr) *t_enter = t0;
    return true;
  }
  for (int k = 0; k < 3; ++k) {
    double a = (lo[k] - p[k]) * inv[k], b = (hi[k] - p[k]) * inv[k];
    if (std::isnan(a) || std::isnan(b)) {
      // Direction component zero and p on a slab plane: treat as inside the slab.
      if (p[k] < lo[k] || p[k] > hi[k]) return false;
      continue;
    }
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return false;
  }
  if (t_enter != nullptr) *t_enter = t0;
  return true;
}

/// Fixed, irrational-looking directions: no axis or diagonal alignment with typical meshes.
const Eigen::Vector3d kDirections[] = {
    Eigen::Vector3d(0.2786151, 0.5213317, 0.8065347).normalized(),
    Eigen::Vector3d(-0.7173561, 0.1953872, -0.6687233).normalized(),
    Eigen::Vector3d(0.4311926, -0.8746251, 0.2214372).normalized(),
    Eigen::Vector3d(-0.1523477, -0.3381629, 0.9287761).normalized(),
    Eigen::Vector3d(0.8361927, 0.3627451, -0.4112693).normalized(),
    Eigen::Vector3d(-0.5571943, 0.7718357, 0.3063629).normalized(),
};

/// Moller-Trumbore after the parallel test: the ray p + t d against the triangle at corner `a`
/// with edges e1, e2, where pvec = d x e2 and det = e1 . pvec (not ~0). False when (u, v) lies
/// outside the triangle grown by kBaryTol; else the ray's t and the barycentric u, v.
bool crossing(const Eigen::Vector3d& p, const Eigen::Vector3d& d, const Eigen::Vector3d& a,
              const Eigen::Vector3d& e1, const Eigen::Vector3d& e2, const Eigen::Vector3d& pvec,
              double det, double* t, double* u, double* v) {
  const double inv_det = 1.0 / det;
  const Eigen::Vector3d s = p - a;
  *u = s.dot(pvec) * inv_det;
  if (*u < -kBaryTol || *u > 1 + kBaryTol) return false;
  const Eigen::Vector3d qvec = s.cross(e1);
  *v = d.dot(qvec) * inv_det;
  if (*v < -kBaryTol || *u + *v > 1 + kBaryTol) return false;
  *t = e2.dot(qvec) * inv_det;
  return true;
}

}  // namespace

MeshBvh::MeshBvh(const TriangleMesh& mesh) {
  const std::size_t n = mesh.faces.size();
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0);
  std::vector<Eigen::Vector3d> centroids(n);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  TriangleBoxes boxes;
  boxes.lo.resize(n);
  boxes.hi.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& f = mesh.faces[i];
    centroids[i] = (mesh.vertices[f[0]] + mesh.vertices[f[1]] + mesh.vertices[f[2]]) / 3.0;
    boxes.lo[i] = boxes.hi[i] = mesh.vertices[f[0]];
    for (int c = 0; c < 3; ++c) {
      boxes.lo[i] = boxes.lo[i].cwiseMin(mesh.vertices[f[c]]);
      boxes.hi[i] = boxes.hi[i].cwiseMax(mesh.vertices[f[c]]);
    }
    lo = lo.cwiseMin(boxes.lo[i]);
    hi = hi.cwiseMax(boxes.hi[i]);
  }
  eps_ = n > 0 ? 1e-12 * (hi - lo).norm() : 0.0;
  if (n > 0) {
    nodes_.reserve(2 * n / kLeafSize + 2);
    // Permutes order_ and fills the triangle corners below.
    a_.resize(n);
    b_.resize(n);
    c_.resize(n);
    e1_.resize(n);
    e2_.resize(n);
    n1_.resize(n);
    n2_.resize(n);
    build(0, static_cast<int>(n), centroids, boxes, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& f = mesh.faces[static_cast<std::size_t>(order_[i])];
      a_[i] = mesh.vertices[f[0]];
      b_[i] = mesh.vertices[f[1]];
      c_[i] = mesh.vertices[f[2]];
      e1_[i] = b_[i] - a_[i];
      e2_[i] = c_[i] - a_[i];
      n1_[i] = e1_[i].norm();
      n2_[i] = e2_[i].norm();
    }
    // Node boxes from the final corners, grown by eps_.
    for (int k = static_cast<int>(nodes_.size()) - 1; k >= 0; --k) {
      Node& node = nodes_[k];
      if (node.left < 0) {
        node.lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
        node.hi = -node.lo;
        for (int i = node.begin; i < node.end; ++i) {
          node.lo = node.lo.cwiseMin(a_[i]).cwiseMin(b_[i]).cwiseMin(c_[i]);
          node.hi = node.hi.cwiseMax(a_[i]).cwiseMax(b_[i]).cwiseMax(c_[i]);
        }
        node.lo.array() -= eps_;
        node.hi.array() += eps_;
      }
    }
    // Children always come after their parent: a reverse sweep fills inner boxes.
    for (int k = static_cast<int>(nodes_.size()) - 1; k >= 0; --k) {
      Node& node = nodes_[k];
      if (node.left >= 0) {
        node.lo = nodes_[node.left].lo.cwiseMin(nodes_[node.right].lo);
        node.hi = nodes_[node.left].hi.cwiseMax(nodes_[node.right].hi);
      }
    }
    buildInsideGrid();
  }
}

int MeshBvh::sahSplit(int begin, int end, const std::vector<Eigen::Vector3d>& centroids,
                      const TriangleBoxes& boxes, const Eigen::Vector3d& lo,
                      const Eigen::Vector3d& hi) {
  struct Bin {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = -lo;
    int count = 0;
  };
  const auto area = [](const Eigen::Vector3d& box_lo, const Eigen::Vector3d& box_hi) {
    const Eigen::Vector3d e = (box_hi - box_lo).cwiseMax(0.0);
    return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
  };
  double best_cost = std::numeric_limits<double>::infinity();
  int best_axis = -1, best_bin = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double extent = hi[axis] - lo[axis];
    if (!(extent > 0.0)) continue;
    std::array<Bin, kSahBins> bins;
    for (int i = begin; i < end; ++i) {
      const int f = order_[i];
      Bin& b = bins[binOf(centroids[f][axis], lo[axis], extent)];
      b.lo = b.lo.cwiseMin(boxes.lo[f]);
      b.hi = b.hi.cwiseMax(boxes.hi[f]);
      ++b.count;
    }
    // Cost of splitting after bin k: area x count of each side, swept from both ends.
    std::array<double, kSahBins> right_cost{};
    Bin acc;
    for (int k = kSahBins - 1; k > 0; --k) {
      acc.lo = acc.lo.cwiseMin(bins[k].lo);
      acc.hi = acc.hi.cwiseMax(bins[k].hi);
      acc.count += bins[k].count;
      right_cost[k] = acc.count > 0 ? area(acc.lo, acc.hi) * acc.count : -1.0;
    }
    acc = Bin();
    for (int k = 0; k + 1 < kSahBins; ++k) {
      acc.lo = acc.lo.cwiseMin(bins[k].lo);
      acc.hi = acc.hi.cwiseMax(bins[k].hi);
      acc.count += bins[k].count;
      if (acc.count == 0 || right_cost[k + 1] < 0.0) continue;
      const double cost = area(acc.lo, acc.hi) * acc.count + right_cost[k + 1];
      if (cost < best_cost) best_cost = cost, best_axis = axis, best_bin = k;
    }
  }
  if (best_axis < 0) return -1;
  const double extent = hi[best_axis] - lo[best_axis];
  const auto mid = std::stable_partition(order_.begin() + begin, order_.begin() + end, [&](int f) {
    return binOf(centroids[f][best_axis], lo[best_axis], extent) <= best_bin;
  });
  return static_cast<int>(mid - order_.begin());
}

int MeshBvh::build(int begin, int end, const std::vector<Eigen::Vector3d>& centroids,
                   const TriangleBoxes& boxes, int depth) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kLeafSize) {
    nodes_[index].begin = begin;
    nodes_[index].end = end;
    return index;
  }
  Eigen::Vector3d lo = centroids[order_[begin]], hi = lo;  // the centroids' box
  for (int i = begin; i < end; ++i) {
    lo = lo.cwiseMin(centroids[order_[i]]);
    hi = hi.cwiseMax(centroids[order_[i]]);
  }
  // Surface-area splits above kMaxSahDepth levels, median splits below (a depth bound for the
  // traversals' fixed stacks: at most kMaxSahDepth + log2(n) levels).
  int mid = depth < kMaxSahDepth ? sahSplit(begin, end, centroids, boxes, lo, hi) : -1;
  if (mid <= begin || mid >= end) {
    int axis = 0;
    (hi - lo).maxCoeff(&axis);
    mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                     [&](int x, int y) {
                       const double cx = centroids[x][axis], cy = centroids[y][axis];
                       return cx < cy || (cx == cy && x < y);
                     });
  }
  const int left = build(begin, mid, centroids, boxes, depth + 1);
  const int right = build(mid, end, centroids, boxes, depth + 1);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

MeshBvh::Parity MeshBvh::rayParity(const Eigen::Vector3d& p, const Eigen::Vector3d& d) const {
  if (nodes_.empty()) return Parity::kOutside;
  const RaySlabs ray(p, d);
  int winding = 0;  // exits minus entries along the ray
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!rayHitsBox(ray, node.lo, node.hi)) continue;
    if (node.left >= 0) {
      stack[top++] = node.left;
      stack[top++] = node.right;
      continue;
    }
    for (int i = node.begin; i < node.end; ++i) {
      const Eigen::Vector3d& e1 = e1_[i];
      const Eigen::Vector3d& e2 = e2_[i];
      const Eigen::Vector3d pvec = d.cross(e2);
      const double det = e1.dot(pvec);
      const Eigen::Vector3d s = p - a_[i];
      const double scale = n1_[i] * n2_[i];
      if (std::abs(det) <= 1e-12 * scale) {
        // Ray parallel to the triangle's plane: only matters if it runs inside the plane.
        const Eigen::Vector3d normal = e1.cross(e2);
        const double nn = normal.norm();
        if (nn == 0 || std::abs(s.dot(normal)) / nn <= eps_) {
          const Eigen::Vector3d q = closestOnTriangle(p, a_[i], b_[i], c_[i]);
          if ((q - p).norm() <= eps_) return Parity::kOnSurface;
          return Parity::kAmbiguous;
        }
        continue;
      }
      double t = 0.0, u = 0.0, v = 0.0;
      if (!crossing(p, d, a_[i], e1, e2, pvec, det, &t, &u, &v)) continue;
      if (t < -eps_) continue;
      if (t <= eps_) return Parity::kOnSurface;
      if (u < kBaryTol || v < kBaryTol || u + v > 1 - kBaryTol) return Parity::kAmbiguous;
      // det = -d . (e1 x e2): negative when the ray leaves through an outward face.
      winding += det < 0 ? 1 : -1;
    }
  }
  return winding > 0 ? Parity::kInside : Parity::kOutside;
}

bool MeshBvh::contains(const Eigen::Vector3d& p) const {
  if (!p.allFinite()) return false;  // gridLabel needs a cell index
  // Outside the root box a cell is free and outside, or the rays' own guard answers false.
  const InsideGrid::Label label = gridLabel(p);
  if (label == InsideGrid::kInside) return true;
  if (label == InsideGrid::kOutside) return false;
  return containsByRays(p);
}

bool MeshBvh::containsByRays(const Eigen::Vector3d& p) const {
  if (nodes_.empty() || !p.allFinite()) return false;
  const Node& root = nodes_[0];
  if ((p.array() < root.lo.array()).any() || (p.array() > root.hi.array()).any()) return false;
  for (const Eigen::Vector3d& d : kDirections) {
    switch (rayParity(p, d)) {
      case Parity::kInside:
        return true;
      case Parity::kOutside:
        return false;
      case Parity::kOnSurface:
        return false;
      case Parity::kAmbiguous:
        break;
    }
  }
  return windingNumber(p) > 0.5;
}

double MeshBvh::closestPoint(const Eigen::Vector3d& p, Eigen::Vector3d* closest, int* face) const {
  double best2 = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best_point = p;
  int best_face = -1;
  if (nodes_.empty()) {
    if (face != nullptr) *face = -1;
    return best2;
  }
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (boxDistance2(p, node.lo, node.hi) >= best2) continue;
    if (node.left >= 0) {
      const double dl = boxDistance2(p, nodes_[node.left].lo, nodes_[node.left].hi);
      const double dr = boxDistance2(p, nodes_[node.right].lo, nodes_[node.right].hi);
      // Push the farther child first so the nearer one is searched first.
      if (dl < dr) {
        stack[top++] = node.right;
        stack[top++] = node.left;
      } else {
        stack[top++] = node.left;
        stack[top++] = node.right;
      }
      continue;
    }
    for (int i = node.begin; i < node.end; ++i) {
      const Eigen::Vector3d q = closestOnTriangle(p, a_[i], b_[i], c_[i]);
      const double d2 = (q - p).squaredNorm();
      if (d2 < best2) {
        best2 = d2;
        best_point = q;
        best_face = order_[i];
      }
    }
  }
  if (closest != nullptr) *closest = best_point;
  if (face != nullptr) *face = best_face;
  return std::sqrt(best2);
}

bool MeshBvh::within(const Eigen::Vector3d& p, double r) const {
  const double r2 = r * r;
  if (nodes_.empty() || !(r > 0.0)) return false;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (boxDistance2(p, node.lo, node.hi) >= r2) continue;
    if (node.left >= 0) {
      stack[top++] = node.right;
      stack[top++] = node.left;
      continue;
    }
    for (int i = node.begin; i < node.end; ++i)
      if ((closestOnTriangle(p, a_[i], b_[i], c_[i]) - p).squaredNorm() < r2) return true;
  }
  return false;
}

// Moller-Trumbore; parallel rays (det ~ 0) do not cross the triangle.
bool MeshBvh::rayCrosses(int i, const Eigen::Vector3d& p, const Eigen::Vector3d& d,
                         double* t) const {
  const Eigen::Vector3d& e1 = e1_[i];
  const Eigen::Vector3d& e2 = e2_[i];
  const Eigen::Vector3d pvec = d.cross(e2);
  const double det = e1.dot(pvec);
  if (std::abs(det) <= 1e-12 * n1_[i] * n2_[i]) return false;
  double u = 0.0, v = 0.0;
  return crossing(p, d, a_[i], e1, e2, pvec, det, t, &u, &v);
}

double MeshBvh::firstHit(const Eigen::Vector3d& p, const Eigen::Vector3d& d, double t_min,
                         double t_max, int* face) const {
  double best = std::numeric_limits<double>::infinity();
  int best_face = -1;
  const RaySlabs ray(p, d);
  // Boxes are searched nearest entry first, and a box entered past the range's end or the
  // best hit so far is skipped: a triangle in a box is crossed no earlier than the box is
  // entered (boxes are grown by eps_; the bound has a relative slack of 1e-9 besides, so
  // rounding never drops the hit the full search would return, ties by face index included).
  const auto bound = [&] { return std::min(t_max, best) * (1.0 + 1e-9) + eps_; };
  double t_root = 0.0;
  if (nodes_.empty() || !rayHitsBox(ray, nodes_[0].lo, nodes_[0].hi, bound(), &t_root)) {
    if (face != nullptr) *face = -1;
    return best;
  }
  std::pair<int, double> stack[128];
  int top = 0;
  stack[top++] = {0, t_root};
  while (top > 0) {
    const auto [index, t_enter] = stack[--top];
    if (t_enter > bound()) continue;
    const Node& node = nodes_[index];
    if (node.left >= 0) {
      double tl = 0.0, tr = 0.0;
      const bool hl = rayHitsBox(ray, nodes_[node.left].lo, nodes_[node.left].hi, bound(), &tl);
      const bool hr = rayHitsBox(ray, nodes_[node.right].lo, nodes_[node.right].hi, bound(), &tr);
      // The farther child is pushed first, so the nearer one is searched first.
      if (hl && hr && tl <= tr) {
        stack[top++] = {node.right, tr};
        stack[top++] = {node.left, tl};
      } else {
        if (hl) stack[top++] = {node.left, tl};
        if (hr) stack[top++] = {node.right, tr};
      }
      continue;
    }
    for (int i = node.begin; i < node.end; ++i) {
      double t = 0.0;
      if (!rayCrosses(i, p, d, &t) || t <= t_min || t > t_max) continue;
      if (t < best || (t == best && order_[i] < best_face)) {
        best = t;
        best_face = order_[i];
      }
    }
  }
  if (face != nullptr) *face = best_face;
  return best;
}

double MeshBvh::firstHitAndAgain(const Eigen::Vector3d& p, const Eigen::Vector3d& d, double t_min,
                                 double t_max, double gap, int* face, bool* again) const {
  double best = std::numeric_limits<double>::infinity();
  double last = -std::numeric_limits<double>::infinity();  // the farthest crossing seen
  int best_face = -1;
  const RaySlabs ray(p, d);
  const double reach = t_max * (1.0 + 1e-9) + eps_;
  int stack[128];
  int top = 0;
  if (!nodes_.empty()) stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!rayHitsBox(ray, node.lo, node.hi, reach)) continue;
    if (node.left >= 0) {
      stack[top++] = node.right;
      stack[top++] = node.left;
      continue;
    }
    for (int i = node.begin; i < node.end; ++i) {
      double t = 0.0;
      if (!rayCrosses(i, p, d, &t) || t <= t_min || t > reach) continue;
      last = std::max(last, t);
      if (t > t_max) continue;
      if (t < best || (t == best && order_[i] < best_face)) {
        best = t;
        best_face = order_[i];
      }
    }
  }
  if (face != nullptr) *face = best_face;
  *again = best_face >= 0 && last > best + gap;
  return best;
}

double MeshBvh::windingNumber(const Eigen::Vector3d& p) const {
  double total = 0;
  for (std::size_t i = 0; i < a_.size(); ++i) {
    const Eigen::Vector3d a = a_[i] - p, b = b_[i] - p, c = c_[i] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double num = a.dot(b.cross(c));
    const double den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    total += 2.0 * std::atan2(num, den);
  }
  return total / (4.0 * M_PI);
}

}  // namespace taskmap::detail
