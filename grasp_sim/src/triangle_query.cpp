// Per-triangle GJK/EPA (TriangleQuery) and the baseline link query through Bullet's BVH.
#include <algorithm>
#include <cmath>
#include <limits>

#include <BulletCollision/CollisionShapes/btTriangleShape.h>

#include "collision_data.hpp"

namespace taskmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

double boxTriangleSeparation(const Eigen::Vector3d& c, const Eigen::Matrix3d& r,
                             const Eigen::Vector3d& e, const btVector3* tri, double limit) {
  Eigen::Vector3d v[3];
  for (int i = 0; i < 3; ++i)
    v[i] = r.transpose() * (Eigen::Vector3d(tri[i].x(), tri[i].y(), tri[i].z()) - c);
  double best = -std::numeric_limits<double>::infinity();
  auto axis = [&](const Eigen::Vector3d& l) {
    const double len = l.norm();
    if (len < 1e-12) return;
    const double p0 = l.dot(v[0]), p1 = l.dot(v[1]), p2 = l.dot(v[2]);
    const double rad = e.x() * std::abs(l.x()) + e.y() * std::abs(l.y()) + e.z() * std::abs(l.z());
    const double lo = std::min({p0, p1, p2}), hi = std::max({p0, p1, p2});
    best = std::max(best, std::max(lo - rad, -rad - hi) / len);
  };
  // The same axes in the same order as without a limit; only the return comes earlier. The
  // box's own axes first, written out: for a unit axis the dot products are the coordinates and
  // the norm is 1, so the arithmetic above gives the same numbers.
  for (int i = 0; i < 3; ++i) {
    const double lo = std::min({v[0][i], v[1][i], v[2][i]});
    const double hi = std::max({v[0][i], v[1][i], v[2][i]});
    best = std::max(best, std::max(lo - e[i], -e[i] - hi));
  }
  if (best > limit) return best;
  const Eigen::Vector3d f[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  axis(f[0].cross(f[1]));
  if (best > limit) return best;
  for (const auto& edge : f) {
    axis(Eigen::Vector3d(0, -edge.z(), edge.y()));
    axis(Eigen::Vector3d(edge.z(), 0, -edge.x()));
    axis(Eigen::Vector3d(-edge.y(), edge.x(), 0));
    if (best > limit) return best;
  }
  return best;
}

/// Signed distance between two convex shapes with GJK (separated) or EPA (overlapping).
/// Returns false when the depth of an overlap is not wanted (`need_depth` false) or EPA failed;
/// `r` then holds what is known. Distances are between the full shapes (margins included).
bool signedDistance(const btConvexShape* a, const btTransform& ta, const btConvexShape* b,
                    const btTransform& tb, bool need_depth, double* distance,
                    btGjkEpaSolver2::sResults* r, bool* overlap) {
  const btVector3 guess = tb.getOrigin() - ta.getOrigin();
  *overlap = false;
  if (btGjkEpaSolver2::Distance(a, ta, b, tb, guess, *r)) {
    // Distance() measures the cores: subtract the margins (sphere radius). The solver returns
    // the normal in the frame of shape a; witnesses are in world coordinates.
    *distance = r->distance - a->getMargin() - b->getMargin();
    r->normal = ta.getBasis() * r->normal;
    return true;
  }
  *overlap = true;
  if (!need_depth) return false;
  if (btGjkEpaSolver2::Penetration(a, ta, b, tb, guess, *r)) {
    *distance = r->distance;
    r->normal = ta.getBasis() * r->normal;
    return true;
  }
  return false;
}

void TriangleQuery::processTriangle(btVector3* tri, int, int index) {
  if (overlap_found && !exact) return;
  if (is_box && exact && sat_depths) {
    // The 13 axes once: the gap, and the depth and witness of an overlap.
    const BoxTrianglePenetration p = boxTrianglePenetration(box_centre, box_axes, box_half, tri);
    if (p.separation > threshold) return;
    if (p.separation < -kSatDepthMin) {
      min_distance = std::min(min_distance, -p.depth);
      if (hits) hits->push_back({-p.depth, p.point, index, p.normal});
      return;
    }
  } else if (is_box) {
    const double sep = boxTriangleSeparation(box_centre, box_axes, box_half, tri,
                                             sat_early_exit ? threshold : kInf);
    if (sep > threshold) return;
    if (sep <= 0.0 && !exact) {
      // The 13 axes give the exact minimum translation distance of the pair: a lower bound
      // of the link's penetration of the whole mesh.
      overlap_found = true;
      min_distance = std::min(min_distance, std::min(sep, kOverlapping));
      return;
    }
  }
  btTriangleShape ts(tri[0], tri[1], tri[2]);
  ts.setMargin(0.0);
  btGjkEpaSolver2::sResults r;
  double d = 0.0;
  bool overlap = false;
  const bool known =
      signedDistance(shape, xf, &ts, btTransform::getIdentity(), exact, &d, &r, &overlap);
  if (!known) {
    if (!exact) {
      overlap_found = true;
      min_distance = std::min(min_distance, kOverlapping);
      return;
    }
    // EPA failed on an overlapping pair: treat as touching at the triangle centroid.
    d = 0.0;
    r.witnesses[1] = (tri[0] + tri[1] + tri[2]) / 3.0;
    r.normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]).normalized();
  }
  if (d > threshold) return;
  min_distance = std::min(min_distance, d);
  if (d < 0.0 && !exact) {
    overlap_found = true;
    return;
  }
  if (hits) {
    TriangleHit h;
    h.distance = d;
    h.point = eig(r.witnesses[1]);
    h.normal = eig(r.normal);
    h.triangle = index;
    hits->push_back(h);
  }
}

TriangleQuery makeTriangleQuery(const ShapeEntry& e, const Eigen::Isometry3d& ts, double threshold,
                                bool exact, std::vector<TriangleHit>* hits) {
  TriangleQuery q;
  q.shape = e.shape.get();
  q.xf = bt(ts);
  q.threshold = threshold;
  q.exact = exact;
  q.hits = hits;
  if (e.is_box) {
    q.is_box = true;
    q.box_centre = ts.translation();
    q.box_axes = ts.linear();
    q.box_half = e.half_extents;
  }
  return q;
}

double queryLinkBullet(const CollisionScene::Data& d, const std::vector<ShapeEntry>& entries,
                       const Eigen::Isometry3d& t, double threshold, bool exact,
                       std::vector<TriangleHit>* hits) {
  double best = kInf;
  for (const ShapeEntry& e : entries) {
    const Eigen::Isometry3d ts = t * e.origin;
    if (beyondObjectBox(d, e, ts, threshold)) continue;
    best = std::min(best, queryShapeBullet(d, e, ts, threshold, exact, hits));
    if (!exact && best < 0.0) break;
  }
  return best;
}

double queryShapeBullet(const CollisionScene::Data& d, const ShapeEntry& e,
                        const Eigen::Isometry3d& ts, double threshold, bool exact,
                        std::vector<TriangleHit>* hits) {
  TriangleQuery q = makeTriangleQuery(e, ts, threshold, exact, hits);
  q.sat_early_exit = d.culled;
  btVector3 amin, amax;
  e.shape->getAabb(q.xf, amin, amax);
  const btVector3 pad(threshold, threshold, threshold);
  d.mesh_shape->processAllTriangles(&q, amin - pad, amax + pad);
  return q.min_distance;
}

}  // namespace taskmap
