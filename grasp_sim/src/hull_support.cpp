// Hull support cells (hull_support.hpp): candidate lists per cube-map cell and the Bullet hull
// shape that scans them.
#include "hull_support.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hull_support_shape.hpp"

namespace taskmap {
namespace {

constexpr int kK = HullSupportCells::kCellsPerEdge;
/// Relative growth of a cell's angular radius and absolute directional slack (radians): far
/// above the rounding of classifying a direction into a cell (~1e-16).
constexpr double kRadiusGrowth = 1.01;
constexpr double kRadiusSlack = 1e-9;
/// A point stays a candidate unless its best dot product over the cell is below the others'
/// guaranteed one by this much times the largest point norm (rounding of the dot products
/// is ~1e-16 of it).
constexpr double kDotSlack = 1e-9;

/// Cube face of direction v (0..5: axis * 2 + negative) and its two face coordinates in [-1, 1].
bool faceOf(double x, double y, double z, int* face, double* u, double* w) {
  const double c[3] = {x, y, z};
  int a = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(c[k]) > std::abs(c[a])) a = k;
  const double m = std::abs(c[a]);
  if (!(m > 0.0) || !std::isfinite(m) || std::isnan(c[(a + 1) % 3]) || std::isnan(c[(a + 2) % 3]))
    return false;
  *face = 2 * a + (c[a] < 0.0 ? 1 : 0);
  *u = c[(a + 1) % 3] / m;
  *w = c[(a + 2) % 3] / m;
  return true;
}

int cellIndex(double u) {
  return std::clamp(static_cast<int>(std::floor((u + 1.0) * 0.5 * kK)), 0, kK - 1);
}

Eigen::Vector3d faceDirection(int face, double u, double w) {
  const int a = face / 2;
  Eigen::Vector3d v;
  v[a] = (face % 2) ? -1.0 : 1.0;
  v[(a + 1) % 3] = u;
  v[(a + 2) % 3] = w;
  return v.normalized();
}

/// Bullet's scan (btVector3::maxDot in double precision): first index of the largest p . v.
int scanAll(const btVector3* pts, int n, const btVector3& v) {
  double best = -SIMD_INFINITY;
  int idx = -1;
  for (int i = 0; i < n; ++i) {
    const double dot = pts[i].dot(v);
    if (dot > best) {
      best = dot;
      idx = i;
    }
  }
  return idx < 0 ? 0 : idx;
}

}  // namespace

HullSupportCells::HullSupportCells(const std::vector<Eigen::Vector3d>& points) {
  if (points.empty()) return;
  double max_norm = 0.0;
  for (const auto& p : points) max_norm = std::max(max_norm, p.norm());
  const double slack = kDotSlack * std::max(max_norm, 1e-300);
  cells_.resize(6 * kK * kK);
  const double h = 2.0 / kK;
  for (int f = 0; f < 6; ++f)
    for (int iu = 0; iu < kK; ++iu)
      for (int iw = 0; iw < kK; ++iw) {
        const double u0 = -1.0 + iu * h, w0 = -1.0 + iw * h;
        const Eigen::Vector3d n0 = faceDirection(f, u0 + 0.5 * h, w0 + 0.5 * h);
        double delta = 0.0;
        for (int c = 0; c < 4; ++c)
          delta =
              std::max(delta, (faceDirection(f, u0 + (c & 1) * h, w0 + (c >> 1) * h) - n0).norm());
        delta = kRadiusGrowth * delta + kRadiusSlack;
        double guaranteed = -std::numeric_limits<double>::infinity();
        for (const auto& p : points)
          guaranteed = std::max(guaranteed, p.dot(n0) - p.norm() * delta);
        auto& list = cells_[static_cast<std::size_t>((f * kK + iu) * kK + iw)];
        for (std::size_t i = 0; i < points.size(); ++i)
          if (points[i].dot(n0) + points[i].norm() * delta >= guaranteed - slack)
            list.push_back(static_cast<int>(i));
      }
}

const std::vector<int>* HullSupportCells::cell(double x, double y, double z) const {
  if (cells_.empty()) return nullptr;
  int f = 0;
  double u = 0.0, w = 0.0;
  if (!faceOf(x, y, z, &f, &u, &w)) return nullptr;
  return &cells_[static_cast<std::size_t>((f * kK + cellIndex(u)) * kK + cellIndex(w))];
}

double HullSupportCells::meanCandidates() const {
  if (cells_.empty()) return 0.0;
  double s = 0.0;
  for (const auto& c : cells_) s += static_cast<double>(c.size());
  return s / static_cast<double>(cells_.size());
}

IndexedHullShape::IndexedHullShape(const std::vector<Eigen::Vector3d>& points, double margin)
    : btConvexHullShape(points.front().data(), static_cast<int>(points.size()),
                        sizeof(Eigen::Vector3d)) {
  optimizeConvexHull();
  setMargin(margin);
  std::vector<Eigen::Vector3d> kept;
  for (int i = 0; i < getNumPoints(); ++i) {
    const btVector3& p = getUnscaledPoints()[i];
    kept.emplace_back(p.x(), p.y(), p.z());
  }
  cells_ = std::make_unique<HullSupportCells>(kept);
  // Not CONVEX_HULL_SHAPE_PROXYTYPE: GJK's non-virtual support then calls the override below.
  m_shapeType = CUSTOM_CONVEX_SHAPE_TYPE;
}

// Same point as btConvexHullShape's scan: the direction scaled, dot products with the unscaled
// points in Bullet's arithmetic, the first largest kept; only the cell's candidates are read.
btVector3 IndexedHullShape::localGetSupportingVertexWithoutMargin(const btVector3& vec) const {
  const int n = getNumPoints();
  if (n == 0) return btVector3(0.0, 0.0, 0.0);
  const btVector3* pts = getUnscaledPoints();
  const btVector3 v = vec * getLocalScalingNV();
  const std::vector<int>* cand = cells_->cell(v.x(), v.y(), v.z());
  if (!cand) return pts[scanAll(pts, n, v)] * getLocalScalingNV();
  double best = -SIMD_INFINITY;
  int idx = -1;
  for (int i : *cand) {
    const double dot = pts[i].dot(v);
    if (dot > best) {
      best = dot;
      idx = i;
    }
  }
  if (idx < 0) idx = scanAll(pts, n, v);
  return pts[idx] * getLocalScalingNV();
}

struct HullSupportCheck::Impl {
  std::unique_ptr<btConvexHullShape> plain;
  std::unique_ptr<IndexedHullShape> indexed;
};

HullSupportCheck::HullSupportCheck(const std::vector<Eigen::Vector3d>& points)
    : d_(std::make_unique<Impl>()) {
  d_->plain = std::make_unique<btConvexHullShape>(
      points.front().data(), static_cast<int>(points.size()), sizeof(Eigen::Vector3d));
  d_->plain->optimizeConvexHull();
  d_->plain->setMargin(0.0);
  d_->indexed = std::make_unique<IndexedHullShape>(points, 0.0);
}

HullSupportCheck::~HullSupportCheck() = default;

namespace {
Eigen::Vector3d toEig(const btVector3& v) {
  return Eigen::Vector3d(v.x(), v.y(), v.z());
}
btVector3 toBt(const Eigen::Vector3d& v) {
  return btVector3(v.x(), v.y(), v.z());
}
}  // namespace

Eigen::Vector3d HullSupportCheck::scan(const Eigen::Vector3d& dir) const {
  return toEig(d_->plain->localGetSupportVertexWithoutMarginNonVirtual(toBt(dir)));
}
Eigen::Vector3d HullSupportCheck::indexed(const Eigen::Vector3d& dir) const {
  return toEig(d_->indexed->localGetSupportVertexWithoutMarginNonVirtual(toBt(dir)));
}
Eigen::Vector3d HullSupportCheck::indexedVirtual(const Eigen::Vector3d& dir) const {
  return toEig(d_->indexed->localGetSupportingVertex(toBt(dir)));
}
Eigen::Vector3d HullSupportCheck::scanVirtual(const Eigen::Vector3d& dir) const {
  return toEig(d_->plain->localGetSupportingVertex(toBt(dir)));
}

}  // namespace taskmap
