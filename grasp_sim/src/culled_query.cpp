// Culled link-versus-object queries (CollisionScene::Mode::kCulled). Same results as the Bullet
// path bit for bit: a triangle is skipped only when a separating plane proves it farther than
// the threshold (so GJK, whose distances are upper bounds, would have skipped it too), and the
// rest go through the same TriangleQuery in the order Bullet's BVH would report them.
#include <algorithm>
#include <cmath>
#include <limits>

#include <LinearMath/btConvexHullComputer.h>

#include "collision_data.hpp"

namespace taskmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// A triangle is culled when a plane puts it farther than threshold + kCullSlack, metres (GJK
/// in double precision is accurate to ~1e-12 relative; this leaves three orders of margin).
constexpr double kCullSlack = 1e-9;
/// A triangle corner deeper than this inside a hull's face planes proves an overlap, metres.
constexpr double kInsideSlack = 1e-6;

/// The 26 directions of a k-DOP: faces, edges and corners of the unit cube.
const std::vector<Eigen::Vector3d>& dopAxes() {
  static const std::vector<Eigen::Vector3d> kAxes = [] {
    std::vector<Eigen::Vector3d> a;
    for (int x = -1; x <= 1; ++x)
      for (int y = -1; y <= 1; ++y)
        for (int z = -1; z <= 1; ++z)
          if (x != 0 || y != 0 || z != 0) a.push_back(Eigen::Vector3d(x, y, z).normalized());
    // Faces first: they cull most.
    std::stable_sort(a.begin(), a.end(), [](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
      return (p.array() != 0.0).count() < (q.array() != 0.0).count();
    });
    return a;
  }();
  return kAxes;
}

/// Max over the shape of n . x (margin included), shape frame.
double supportOf(const btConvexShape& s, const Eigen::Vector3d& n) {
  return n.dot(eig(s.localGetSupportingVertex(bt(n))));
}

/// Outward unit normals of the faces of the convex hull of `points`.
std::vector<Eigen::Vector3d> hullFaceNormals(const std::vector<Eigen::Vector3d>& points) {
  std::vector<Eigen::Vector3d> normals;
  if (points.size() < 4) return normals;
  btConvexHullComputer hc;
  hc.compute(points.front().data(), static_cast<int>(sizeof(Eigen::Vector3d)),
             static_cast<int>(points.size()), 0.0, 0.0);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int v = 0; v < hc.vertices.size(); ++v) centre += eig(hc.vertices[v]);
  if (hc.vertices.size() > 0) centre /= hc.vertices.size();
  for (int f = 0; f < hc.faces.size(); ++f) {
    const btConvexHullComputer::Edge* e0 = &hc.edges[hc.faces[f]];
    const btConvexHullComputer::Edge* e = e0;
    Eigen::Vector3d n = Eigen::Vector3d::Zero(), on = Eigen::Vector3d::Zero();
    int guard = 0;
    do {  // Newell's normal of the face polygon
      const Eigen::Vector3d a = eig(hc.vertices[e->getSourceVertex()]);
      const Eigen::Vector3d b = eig(hc.vertices[e->getTargetVertex()]);
      n += a.cross(b);
      on = a;
      e = e->getNextEdgeOfFace();
    } while (e != e0 && ++guard < 1000);
    if (n.norm() < 1e-15) continue;
    n.normalize();
    if (n.dot(on - centre) < 0.0) n = -n;
    normals.push_back(n);
  }
  return normals;
}

}  // namespace

void addCullingData(const std::vector<Eigen::Vector3d>& hull_points, ShapeEntry* e) {
  // Boxes: their 6 face planes are exact. Hulls: their own face planes (exact; the 26-DOP when
  // the hull is degenerate). Cylinders and spheres: the 26-DOP.
  const auto& dop = dopAxes();
  e->is_hull = !hull_points.empty();
  e->axes.clear();
  e->facet_begin = 0;
  if (e->is_box) {
    e->axes.assign(dop.begin(), dop.begin() + 6);
  } else if (e->is_hull) {
    e->axes = hullFaceNormals(hull_points);
    if (e->axes.size() < 4) {
      e->axes = dop;
      e->is_hull = false;  // no face planes: no inside shortcut
    }
  } else {
    e->axes = dop;
  }
  e->reach.clear();
  for (const auto& n : e->axes) e->reach.push_back(supportOf(*e->shape, n));
}

void buildCulling(const std::vector<Eigen::Vector3d>& vertices,
                  const std::vector<Eigen::Vector3i>& faces, CollisionScene::Data* d) {
  d->culled = true;
  d->bvh = std::make_unique<TriangleBvh>(vertices, faces);
  d->corners.resize(faces.size());
  for (std::size_t t = 0; t < faces.size(); ++t)
    for (int k = 0; k < 3; ++k)
      d->corners[t][static_cast<std::size_t>(k)] = vertices[static_cast<std::size_t>(faces[t][k])];
  // Bullet's stackless walk reports overlapping leaves in the order of its node array.
  d->rank.assign(faces.size(), -1);
  int next = 0;
  btOptimizedBvh* bvh = d->mesh_shape->getOptimizedBvh();
  if (bvh && bvh->isQuantized()) {
    const auto& nodes = bvh->getQuantizedNodeArray();
    for (int i = 0; i < nodes.size(); ++i) {
      if (!nodes[i].isLeafNode()) continue;
      const int tri = nodes[i].getTriangleIndex();
      if (tri >= 0 && tri < static_cast<int>(faces.size()) &&
          d->rank[static_cast<std::size_t>(tri)] < 0)
        d->rank[static_cast<std::size_t>(tri)] = next++;
    }
  }
  for (auto& r : d->rank)
    if (r < 0) r = next++;
}

double queryLinkCulled(const CollisionScene::Data& d, const std::vector<ShapeEntry>& entries,
                       const Eigen::Isometry3d& t, double threshold, bool exact,
                       std::vector<TriangleHit>* hits) {
  thread_local std::vector<int> cand;
  thread_local std::vector<Eigen::Vector3d> wn;
  thread_local std::vector<double> wh;
  double best = kInf;
  for (const ShapeEntry& e : entries) {
    const Eigen::Isometry3d ts = t * e.origin;
    const Eigen::Vector3d c = ts.translation();
    const Eigen::Vector3d out = (d.lo - c).cwiseMax(c - d.hi).cwiseMax(0.0);
    if (out.norm() > e.bounding_radius + threshold) continue;
    TriangleQuery q = makeTriangleQuery(e, ts, threshold, exact, hits);
    btVector3 amin, amax;
    e.shape->getAabb(q.xf, amin, amax);
    const btVector3 pad(threshold, threshold, threshold);
    const Eigen::Vector3d qlo = eig(amin - pad), qhi = eig(amax + pad);
    // Planes in the object frame: a point set with min over it of wn . x > wh is culled.
    const std::size_t k = e.axes.size();
    wn.resize(k);
    wh.resize(k);
    for (std::size_t i = 0; i < k; ++i) {
      wn[i] = ts.linear() * e.axes[i];
      wh[i] = e.reach[i] + wn[i].dot(c) + threshold + kCullSlack;
    }
    const bool shortcut = !exact && e.is_hull && k > static_cast<std::size_t>(e.facet_begin);
    bool inside_found = false;
    auto accept = [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
      if (inside_found) return false;
      if ((lo.array() > qhi.array()).any() || (hi.array() < qlo.array()).any()) return false;
      const Eigen::Vector3d mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
      for (std::size_t i = 0; i < k; ++i)
        if (wn[i].dot(mid) - wn[i].cwiseAbs().dot(half) > wh[i]) return false;
      return true;
    };
    cand.clear();
    auto leaf = [&](int tri) {
      const auto& v = d.corners[static_cast<std::size_t>(tri)];
      const Eigen::Vector3d tlo = v[0].cwiseMin(v[1]).cwiseMin(v[2]);
      const Eigen::Vector3d thi = v[0].cwiseMax(v[1]).cwiseMax(v[2]);
      if ((tlo.array() > qhi.array()).any() || (thi.array() < qlo.array()).any()) return;
      for (std::size_t i = 0; i < k; ++i)
        if (std::min({wn[i].dot(v[0]), wn[i].dot(v[1]), wn[i].dot(v[2])}) > wh[i]) return;
      cand.push_back(tri);
      if (!shortcut || inside_found) return;
      // A corner strictly inside every face plane of a (margin-free) hull: GJK reports the
      // overlap whichever triangle comes first, and the shape's result is kOverlapping.
      for (const auto& p : v) {
        double worst = -kInf;
        for (std::size_t i = static_cast<std::size_t>(e.facet_begin); i < k && worst < 0.0; ++i)
          worst = std::max(worst, wn[i].dot(p) - (wh[i] - threshold - kCullSlack));
        if (worst < -kInsideSlack) inside_found = true;
      }
    };
    d.bvh->visit(accept, leaf);
    if (inside_found) {
      best = std::min(best, kOverlapping);
      break;
    }
    std::sort(cand.begin(), cand.end(), [&](int x, int y) {
      return d.rank[static_cast<std::size_t>(x)] < d.rank[static_cast<std::size_t>(y)];
    });
    btVector3 tri[3];
    for (int c_tri : cand) {
      if (q.overlap_found && !exact) break;
      const auto& v = d.corners[static_cast<std::size_t>(c_tri)];
      for (int j = 0; j < 3; ++j) tri[j] = bt(v[static_cast<std::size_t>(j)]);
      q.processTriangle(tri, 0, c_tri);
    }
    best = std::min(best, q.min_distance);
    if (!exact && best < 0.0) break;
  }
  return best;
}

}  // namespace taskmap
