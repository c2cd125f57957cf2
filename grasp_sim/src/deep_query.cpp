// Deep-press test (CollisionScene::linkPressesDeeper): does a link penetrate some facing triangle
// deeper than a given depth? Same answer as scanning linkHits (the baseline), with EPA only on
// the triangles whose depth bound exceeds the depth (docs/METHOD.md §2).
#include <cmath>
#include <limits>
#include <vector>

#include "collision_data.hpp"
#include "culled_planes.hpp"

namespace taskmap {
namespace {

/// True when a triangle hit penetrates deeper than `depth` on a face the link presses
/// (separation direction within acos(min_agreement) of the face normal).
bool deepFacing(const CollisionScene::Data& d, const std::vector<TriangleHit>& hits, double depth,
                double min_agreement) {
  for (const TriangleHit& h : hits)
    if (-h.distance > depth &&
        h.normal.dot(d.normals[static_cast<std::size_t>(h.triangle)]) >= min_agreement)
      return true;
  return false;
}

/// One shape of queryLinkDeeper. The penetration depth of a convex shape and a triangle is at
/// most their overlap along any unit axis n, max_shape(n.x) - min_triangle(n.x) (moving the
/// triangle that far along n separates them); the planes give minus that overlap as their
/// term, so a term above kCullSlack - depth proves the pair no deeper than `depth`, and so is
/// EPA's depth (EPA's polytope lies inside the Minkowski difference). Boxes add the exact
/// 13-axis depth.
bool shapeDeeper(const CollisionScene::Data& d, const ShapeEntry& e, const Eigen::Isometry3d& ts,
                 double threshold, double depth, double min_agreement) {
  thread_local ShapePlanes pl;
  thread_local std::vector<TriangleHit> hits;
  const double c = kCullSlack - depth;
  TriangleQuery q = makeTriangleQuery(e, ts, threshold, true, &hits);
  btVector3 amin, amax;
  e.shape->getAabb(q.xf, amin, amax);
  pl.set(e, ts, amin, amax, 0.0);
  bool found = false;
  walkInBulletOrder(
      *d.mesh_shape->getOptimizedBvh(),
      [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
        return pl.nodeBound(lo, hi, c) <= c;
      },
      [&](int tri) {
        const auto& v = d.corners[static_cast<std::size_t>(tri)];
        if (pl.bound(v, c) > c) return true;
        if (e.is_box) {
          const btVector3 corners[3] = {bt(v[0]), bt(v[1]), bt(v[2])};
          if (boxTriangleSeparation(q.box_centre, q.box_axes, q.box_half, corners) > c) return true;
        }
        hits.clear();
        runTriangle(d, tri, &q);
        found = deepFacing(d, hits, depth, min_agreement);
        return !found;
      });
  return found;
}

}  // namespace

bool queryLinkDeeper(const CollisionScene::Data& d, const std::vector<ShapeEntry>& entries,
                     const Eigen::Isometry3d& t, double threshold, double depth,
                     double min_agreement) {
  for (const ShapeEntry& e : entries) {
    const Eigen::Isometry3d ts = t * e.origin;
    // The baseline's cull (queryLinkBullet): the shape's bounding sphere against the object box.
    const Eigen::Vector3d c = ts.translation();
    const Eigen::Vector3d out = (d.lo - c).cwiseMax(c - d.hi).cwiseMax(0.0);
    if (out.norm() > e.bounding_radius + threshold) continue;
    if (d.culled) {
      if (shapeDeeper(d, e, ts, threshold, depth, min_agreement)) return true;
    } else {
      thread_local std::vector<TriangleHit> hits;
      hits.clear();
      queryShapeBullet(d, e, ts, threshold, true, &hits);
      if (deepFacing(d, hits, depth, min_agreement)) return true;
    }
  }
  return false;
}

}  // namespace taskmap
