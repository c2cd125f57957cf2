// CollisionScene: construction of the Bullet shapes, inside test, link-link distances; the
// link-versus-object queries are in triangle_query.cpp (Bullet's BVH) and culled_query.cpp.
#include "collision_scene.hpp"
#include "collision_data.hpp"
#include "hull_support_shape.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <BulletCollision/CollisionShapes/btTriangleIndexVertexArray.h>
#include <BulletCollision/CollisionShapes/btTriangleShape.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpa2.h>
#include <BulletCollision/NarrowPhaseCollision/btRaycastCallback.h>

#include "taskmap/core/error.hpp"

static_assert(sizeof(btScalar) == sizeof(double),
              "taskmap needs Bullet built with double precision");

namespace taskmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Collision margin of the box, cylinder and hull link shapes: none, so that GJK works on the
/// exact shapes (spheres keep their radius as margin; distances subtract it).
constexpr double kConvexMargin = 0.0;
/// linkLinkDistance's axis test skips GJK when the gap exceeds the threshold by this, metres
/// (GJK in double precision is accurate to ~1e-12; as the culled queries' kCullSlack).
constexpr double kAxisSlack = 1e-9;

/// Separating-axis bound between two oriented boxes (15 axes): > 0 is a lower bound on their
/// distance, <= 0 means they intersect. Stops at the first axis that puts it above `limit`
/// (some value > limit is returned; at or below it, the full maximum).
double boxBoxSeparation(const Eigen::Vector3d& ca, const Eigen::Matrix3d& ra,
                        const Eigen::Vector3d& ea, const Eigen::Vector3d& cb,
                        const Eigen::Matrix3d& rb, const Eigen::Vector3d& eb, double limit) {
  const Eigen::Vector3d d = cb - ca;
  double best = -std::numeric_limits<double>::infinity();
  auto axis = [&](const Eigen::Vector3d& l) {
    const double len = l.norm();
    if (len < 1e-12) return false;
    double rad = 0.0;
    for (int k = 0; k < 3; ++k)
      rad += ea[k] * std::abs(l.dot(ra.col(k))) + eb[k] * std::abs(l.dot(rb.col(k)));
    best = std::max(best, (std::abs(l.dot(d)) - rad) / len);
    return best > limit;
  };
  for (int k = 0; k < 3; ++k)
    if (axis(ra.col(k)) || axis(rb.col(k))) return best;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (axis(ra.col(i).cross(rb.col(j)))) return best;
  return best;
}

/// Counts ray crossings with the mesh (parity test).
struct CrossingCounter : btTriangleRaycastCallback {
  CrossingCounter(const btVector3& from, const btVector3& to)
      : btTriangleRaycastCallback(from, to, kF_KeepUnflippedNormal) {}
  int crossings = 0;
  btScalar reportHit(const btVector3&, btScalar, int, int) override {
    ++crossings;
    return m_hitFraction;  // keep collecting every crossing
  }
};

/// A box in the link frame holding every shape of a link (its support along the six axis
/// directions, margins included): centre and half extents; zero without shapes.
std::array<Eigen::Vector3d, 2> linkBox(const std::vector<ShapeEntry>& entries) {
  if (entries.empty()) return {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(kInf), hi = -lo;
  for (const ShapeEntry& e : entries)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d axis = Eigen::Vector3d::Unit(k);
      const Eigen::Vector3d in_shape = e.origin.linear().transpose() * axis;
      const double at = e.origin.translation()[k];
      // max and min over the shape of axis . x: the support along +-in_shape (shape frame).
      const btVector3 up = e.shape->localGetSupportingVertex(bt(in_shape));
      const btVector3 down = e.shape->localGetSupportingVertex(bt(Eigen::Vector3d(-in_shape)));
      hi[k] = std::max(hi[k], at + in_shape.dot(eig(up)));
      lo[k] = std::min(lo[k], at + in_shape.dot(eig(down)));
    }
  return {0.5 * (lo + hi), 0.5 * (hi - lo)};
}

}  // namespace

void buildObjectTree(const TriangleMesh& mesh, CollisionScene::Data* out) {
  CollisionScene::Data& d = *out;
  d.lo = d.hi = mesh.vertices.front();
  for (const auto& v : mesh.vertices) {
    d.vertices.insert(d.vertices.end(), {v.x(), v.y(), v.z()});
    d.lo = d.lo.cwiseMin(v);
    d.hi = d.hi.cwiseMax(v);
  }
  d.centre = 0.5 * (d.lo + d.hi);
  d.radius = 0.5 * (d.hi - d.lo).norm();
  const int nv = static_cast<int>(mesh.vertices.size());
  for (const auto& f : mesh.faces) {
    for (int k = 0; k < 3; ++k)
      if (f[k] < 0 || f[k] >= nv)
        throw Error("grasp simulation: mesh face indexes a missing vertex");
    d.indices.insert(d.indices.end(), {f[0], f[1], f[2]});
    const Eigen::Vector3d n = (mesh.vertices[static_cast<std::size_t>(f[1])] -
                               mesh.vertices[static_cast<std::size_t>(f[0])])
                                  .cross(mesh.vertices[static_cast<std::size_t>(f[2])] -
                                         mesh.vertices[static_cast<std::size_t>(f[0])]);
    const double len = n.norm();
    d.normals.push_back(len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::UnitZ());
  }
  btIndexedMesh im;
  im.m_numTriangles = static_cast<int>(mesh.faces.size());
  im.m_triangleIndexBase = reinterpret_cast<const unsigned char*>(d.indices.data());
  im.m_triangleIndexStride = 3 * sizeof(int);
  im.m_numVertices = nv;
  im.m_vertexBase = reinterpret_cast<const unsigned char*>(d.vertices.data());
  im.m_vertexStride = 3 * sizeof(double);
  im.m_indexType = PHY_INTEGER;
  im.m_vertexType = PHY_DOUBLE;
  d.arrays = std::make_unique<btTriangleIndexVertexArray>();
  d.arrays->addIndexedMesh(im, PHY_INTEGER);
  d.mesh_shape = std::make_unique<btBvhTriangleMeshShape>(d.arrays.get(), true, true);
  d.mesh_shape->setMargin(0.0);
}

CollisionScene::CollisionScene(const TriangleMesh& mesh, const HandModel& hand, Mode mode,
                               bool separating_axis_contacts)
    : d_(std::make_unique<Data>()) {
  if (mesh.faces.empty() || mesh.vertices.size() < 3)
    throw Error("grasp simulation needs a non-empty triangle mesh");
  Data& d = *d_;
  buildObjectTree(mesh, &d);
  if (mode != Mode::kBullet)
    buildCulling(mesh.vertices, mesh.faces,
                 mode == Mode::kCulled || mesh.faces.size() >= kCulledMinFaces, &d);

  for (const HandLink& link : hand.links()) {
    std::vector<ShapeEntry> entries;
    for (const CollisionShape& s : link.shapes) {
      ShapeEntry e;
      e.origin = s.origin;
      e.bounding_radius = s.boundingRadius() + kConvexMargin;
      switch (s.type) {
        case ShapeType::kBox:
          e.is_box = true;
          e.sat_depths = separating_axis_contacts && d.culled_boxes;
          e.half_extents = 0.5 * s.box_size;
          e.shape = std::make_unique<btBoxShape>(bt(Eigen::Vector3d(0.5 * s.box_size)));
          e.shape->setMargin(kConvexMargin);
          break;
        case ShapeType::kCylinder:
          e.shape =
              std::make_unique<btCylinderShapeZ>(btVector3(s.radius, s.radius, 0.5 * s.length));
          e.shape->setMargin(kConvexMargin);
          break;
        case ShapeType::kSphere:
          e.shape = std::make_unique<btSphereShape>(s.radius);
          break;
        case ShapeType::kConvex: {
          e.sat_depths = separating_axis_contacts && d.culled_boxes;
          if (mode != Mode::kBullet) {  // support cells (hull_support.hpp): same points, faster
            e.shape = std::make_unique<IndexedHullShape>(s.points, kConvexMargin);
            break;
          }
          auto hull = std::make_unique<btConvexHullShape>(
              s.points.front().data(), static_cast<int>(s.points.size()), sizeof(Eigen::Vector3d));
          hull->optimizeConvexHull();
          hull->setMargin(kConvexMargin);
          e.shape = std::move(hull);
          break;
        }
      }
      addCullingData(s.type == ShapeType::kConvex ? s.points : std::vector<Eigen::Vector3d>{}, &e);
      entries.push_back(std::move(e));
    }
    // Bounding sphere of the link: centred at the mean of its shape centres.
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto& e : entries) centre += e.origin.translation();
    if (!entries.empty()) centre /= static_cast<double>(entries.size());
    double radius = 0.0;
    for (const auto& e : entries)
      radius = std::max(radius, (e.origin.translation() - centre).norm() + e.bounding_radius);
    d.link_centre.push_back(centre);
    d.link_radius.push_back(radius);
    d.link_box.push_back(linkBox(entries));
    d.links.push_back(std::move(entries));
  }
}

CollisionScene::~CollisionScene() = default;

const Eigen::Vector3d& CollisionScene::faceNormal(int tri) const {
  return d_->normals[static_cast<std::size_t>(tri)];
}
const Eigen::Vector3d& CollisionScene::objectCentre() const {
  return d_->centre;
}
double CollisionScene::objectRadius() const {
  return d_->radius;
}

double CollisionScene::linkDistance(int link, const Eigen::Isometry3d& t, double threshold) const {
  const Data& d = *d_;
  const auto& entries = d.links[static_cast<std::size_t>(link)];
  return d.culled ? queryLinkCulled(d, entries, t, threshold, false, nullptr)
                  : queryLinkBullet(d, entries, t, threshold, false, nullptr);
}

double CollisionScene::linkDistance(int link, const Eigen::Isometry3d& t, double threshold,
                                    SeenTriangles* seen) const {
  const Data& d = *d_;
  const auto& entries = d.links[static_cast<std::size_t>(link)];
  if (!d.culled) {
    seen->complete = false;
    return queryLinkBullet(d, entries, t, threshold, false, nullptr);
  }
  const double dist = queryLinkCulled(d, entries, t, threshold, false, nullptr, false, seen);
  seen->link = link;
  return dist;
}

double CollisionScene::linkHits(int link, const Eigen::Isometry3d& t, double threshold,
                                std::vector<TriangleHit>* hits) const {
  const Data& d = *d_;
  const auto& entries = d.links[static_cast<std::size_t>(link)];
  return d.culled ? queryLinkCulled(d, entries, t, threshold, true, hits, true)
                  : queryLinkBullet(d, entries, t, threshold, true, hits);
}

bool CollisionScene::linkPressesDeeper(int link, const Eigen::Isometry3d& t, double threshold,
                                       double depth, double min_agreement) const {
  const Data& d = *d_;
  if (d.corners.empty()) {  // Mode::kBullet: scan the exact hits
    std::vector<TriangleHit> hits;
    linkHits(link, t, threshold, &hits);
    for (const TriangleHit& h : hits)
      if (-h.distance > depth && h.normal.dot(faceNormal(h.triangle)) >= min_agreement) return true;
    return false;
  }
  return queryLinkDeeper(d, d.links[static_cast<std::size_t>(link)], t, threshold, depth,
                         min_agreement);
}

double CollisionScene::linkNearest(int link, const Eigen::Isometry3d& t, double threshold,
                                   const FacingFilter* filter, TriangleHit* hit) const {
  const Data& d = *d_;
  if (d.corners.empty()) {  // Mode::kBullet: scan the exact hits
    std::vector<TriangleHit> hits;
    linkHits(link, t, threshold, &hits);
    const TriangleHit* best = nullptr;
    for (const TriangleHit& h : hits)
      if ((!filter || filter->passes(faceNormal(h.triangle), h)) &&
          (!best || h.distance < best->distance))
        best = &h;
    if (!best) return std::numeric_limits<double>::infinity();
    if (hit) *hit = *best;
    return best->distance;
  }
  return queryLinkNearest(d, d.links[static_cast<std::size_t>(link)], t, threshold, filter, hit);
}

double CollisionScene::linkNearest(int link, const Eigen::Isometry3d& t, double threshold,
                                   const FacingFilter* filter, TriangleHit* hit,
                                   const SeenTriangles& seen) const {
  const Data& d = *d_;
  const auto& entries = d.links[static_cast<std::size_t>(link)];
  // A link of one box (its walk was recorded): the shape the walk asked about.
  if (!seen.answers(link, t, threshold) || entries.size() != 1)
    return linkNearest(link, t, threshold, filter, hit);
  return queryLinkNearestSeen(d, entries[0], t * entries[0].origin, threshold, filter, hit, seen);
}

bool CollisionScene::linkInside(int link, const Eigen::Isometry3d& t) const {
  const Data& d = *d_;
  static const Eigen::Vector3d kDirs[3] = {Eigen::Vector3d(0.5772, 0.5811, 0.5737).normalized(),
                                           Eigen::Vector3d(-0.3131, 0.8927, -0.3241).normalized(),
                                           Eigen::Vector3d(0.7071, -0.2903, -0.6449).normalized()};
  for (const ShapeEntry& e : d.links[static_cast<std::size_t>(link)]) {
    const Eigen::Vector3d c = (t * e.origin).translation();
    if ((c.array() <= d.lo.array()).any() || (c.array() >= d.hi.array()).any()) continue;
    int votes = 0;
    const double len = 4.0 * d.radius + 1.0;
    for (const auto& dir : kDirs) {
      CrossingCounter counter(bt(c), bt(Eigen::Vector3d(c + len * dir)));
      d.mesh_shape->performRaycast(&counter, bt(c), bt(Eigen::Vector3d(c + len * dir)));
      votes += counter.crossings % 2;
    }
    if (votes >= 2) return true;
  }
  return false;
}

Eigen::Vector3d CollisionScene::linkCentre(int link, const Eigen::Isometry3d& t) const {
  return t * d_->link_centre[static_cast<std::size_t>(link)];
}

double CollisionScene::linkRadius(int link) const {
  return d_->link_radius[static_cast<std::size_t>(link)];
}

namespace {

/// Largest n . x over the shapes of a link at pose t (object frame; margins included).
double linkReach(const std::vector<ShapeEntry>& entries, const Eigen::Isometry3d& t,
                 const Eigen::Vector3d& n) {
  double hi = -kInf;
  for (const ShapeEntry& e : entries) {
    const Eigen::Isometry3d ts = t * e.origin;
    const Eigen::Vector3d local = ts.linear().transpose() * n;
    hi = std::max(hi, n.dot(ts * eig(e.shape->localGetSupportingVertex(bt(local)))));
  }
  return hi;
}

}  // namespace

double CollisionScene::linkLinkDistance(int a, const Eigen::Isometry3d& ta, int b,
                                        const Eigen::Isometry3d& tb, double threshold,
                                        Eigen::Vector3d* axis, bool* apart) const {
  const Data& d = *d_;
  const auto ua = static_cast<std::size_t>(a), ub = static_cast<std::size_t>(b);
  if (apart) *apart = true;
  if ((ta * d.link_centre[ua] - tb * d.link_centre[ub]).norm() >
      d.link_radius[ua] + d.link_radius[ub] + threshold)
    return kInf;
  const auto& la = d.links[ua];
  const auto& lb = d.links[ub];
  // Only pairs with a hull: GJK on boxes, cylinders and spheres costs about what the test does.
  auto hasHull = [](const std::vector<ShapeEntry>& l) {
    return std::any_of(l.begin(), l.end(), [](const ShapeEntry& e) { return e.is_hull; });
  };
  if (axis && !hasHull(la) && !hasHull(lb)) axis = nullptr;
  if (axis && !axis->isZero()) {
    // Separating-axis gap: min over b of n . x minus max over a, a lower bound of the distance.
    const Eigen::Vector3d n = ta.linear() * *axis;
    if (-linkReach(lb, tb, -n) - linkReach(la, ta, n) > threshold + kAxisSlack) return kInf;
  }
  if (apart) *apart = false;
  double best = kInf, nearest_separated = kInf;
  for (const ShapeEntry& ea : la) {
    const Eigen::Isometry3d sa = ta * ea.origin;
    for (const ShapeEntry& eb : lb) {
      const Eigen::Isometry3d sb = tb * eb.origin;
      if ((sa.translation() - sb.translation()).norm() >
          ea.bounding_radius + eb.bounding_radius + threshold)
        continue;
      if (ea.is_box && eb.is_box &&
          boxBoxSeparation(sa.translation(), sa.linear(), ea.half_extents, sb.translation(),
                           sb.linear(), eb.half_extents, threshold) > threshold)
        continue;
      btGjkEpaSolver2::sResults r;
      double dist = 0.0;
      bool overlap = false;
      if (!signedDistance(ea.shape.get(), bt(sa), eb.shape.get(), bt(sb), true, &dist, &r,
                          &overlap))
        dist = 0.0;  // EPA failure on overlapping shapes: treat as touching
      if (dist <= threshold) best = std::min(best, dist);
      if (axis && !overlap && dist < nearest_separated) {
        const Eigen::Vector3d w = eig(r.witnesses[1]) - eig(r.witnesses[0]);
        if (w.norm() > 1e-12) {
          nearest_separated = dist;
          *axis = ta.linear().transpose() * w.normalized();
        }
      }
    }
  }
  return best;
}

}  // namespace taskmap
