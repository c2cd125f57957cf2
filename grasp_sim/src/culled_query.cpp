// Culled link-versus-object queries (CollisionScene::Mode::kCulled). Same results as the Bullet
// path bit for bit: a triangle is skipped only when a separating plane proves it farther than
// the threshold (so GJK, whose distances are upper bounds, would have skipped it too), and the
// rest go through the same TriangleQuery in the order Bullet's BVH would report them.
#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include <LinearMath/btConvexHullComputer.h>

#include "collision_data.hpp"
#include "culled_planes.hpp"

namespace taskmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Box overlap queries within this threshold take one walk (boxOverlapQuery), metres.
constexpr double kOneWalkThreshold = 1e-3;
/// Hull planes tested on triangles: face normals at least this far apart, radians.
constexpr double kBoundPlaneAngle = 0.15;

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

/// An order of the face normals in which each run of kPlaneBlock holds close normals: a seed
/// (the first face not yet placed), then the kPlaneBlock - 1 unplaced normals nearest to it.
std::vector<int> groupFaceNormals(const std::vector<Eigen::Vector3d>& normals) {
  const int n = static_cast<int>(normals.size());
  std::vector<int> order;
  std::vector<char> placed(normals.size(), 0);
  std::vector<std::pair<double, int>> near;
  for (int seed = 0; seed < n; ++seed) {
    if (placed[static_cast<std::size_t>(seed)]) continue;
    near.clear();
    for (int i = 0; i < n; ++i)
      if (!placed[static_cast<std::size_t>(i)])
        near.emplace_back(
            -normals[static_cast<std::size_t>(i)].dot(normals[static_cast<std::size_t>(seed)]), i);
    const auto take = std::min<std::size_t>(kPlaneBlock, near.size());
    std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(take), near.end());
    for (std::size_t k = 0; k < take; ++k) {
      order.push_back(near[k].second);
      placed[static_cast<std::size_t>(near[k].second)] = 1;
    }
  }
  return order;
}

/// The per-block axis, chord and smallest reach of the face planes (ShapeEntry::bx...), and
/// their ranks: `order` maps each face slot to its index in the hull computation's order.
void addFaceBlocks(const std::vector<int>& order, ShapeEntry* e) {
  const int total = static_cast<int>(e->pr.size());
  const int blocks = (total - e->facet_begin) / kPlaneBlock;
  for (Eigen::ArrayXd* a : {&e->bx, &e->by, &e->bz, &e->bchord, &e->bmin}) a->setZero(blocks);
  e->face_rank.assign(static_cast<std::size_t>(total - e->facet_begin),
                      std::numeric_limits<int>::max());
  for (std::size_t i = 0; i < order.size(); ++i) e->face_rank[i] = order[i];
  for (int b = 0; b < blocks; ++b) {
    const int first = e->facet_begin + b * kPlaneBlock;
    const int real = std::min(kPlaneBlock, static_cast<int>(order.size()) - b * kPlaneBlock);
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    for (int i = first; i < first + real; ++i)
      axis += Eigen::Vector3d(e->px[i], e->py[i], e->pz[i]);
    axis = axis.norm() > 1e-12 ? axis.normalized() : Eigen::Vector3d::UnitZ();
    double chord = 0.0, reach = std::numeric_limits<double>::infinity();
    for (int i = first; i < first + real; ++i) {
      chord = std::max(chord, (Eigen::Vector3d(e->px[i], e->py[i], e->pz[i]) - axis).norm());
      reach = std::min(reach, e->pr[i]);
    }
    e->bx[b] = axis.x();
    e->by[b] = axis.y();
    e->bz[b] = axis.z();
    e->bchord[b] = chord;
    e->bmin[b] = reach;
  }
}

}  // namespace

void addCullingData(const std::vector<Eigen::Vector3d>& hull_points, ShapeEntry* e) {
  // Boxes: their 6 face planes are exact. Hulls: the 26-DOP (cheap, for tree nodes), then their
  // own face planes (exact, for triangles; none when the hull is degenerate). Cylinders and
  // spheres: the 26-DOP.
  const auto& dop = dopAxes();
  e->is_hull = !hull_points.empty();
  std::vector<Eigen::Vector3d> axes(dop.begin(), dop.begin() + (e->is_box ? 6 : 26));
  std::vector<Eigen::Vector3d> faces;
  if (e->is_hull) {
    faces = hullFaceNormals(hull_points);
    if (faces.size() < 4) {
      faces.clear();
      e->is_hull = false;  // no face planes: no inside proof
    }
  }
  std::vector<Eigen::Vector3d> spread;  // face normals kBoundPlaneAngle apart at least
  for (const auto& n : faces)
    if (std::none_of(spread.begin(), spread.end(), [&](const Eigen::Vector3d& m) {
          return n.dot(m) > std::cos(kBoundPlaneAngle);
        }))
      spread.push_back(n);
  auto padded = [](std::size_t n) {
    return static_cast<int>((n + kPlaneBlock - 1) / kPlaneBlock * kPlaneBlock);
  };
  e->node_planes = padded(axes.size());
  e->facet_begin = e->node_planes + padded(spread.size());
  const int total = e->facet_begin + padded(faces.size());
  // Padding: normal 0 and reach +inf, a plane no point set is beyond.
  e->px.setZero(total);
  e->py.setZero(total);
  e->pz.setZero(total);
  e->pr.setConstant(total, std::numeric_limits<double>::infinity());
  auto put = [e](int i, const Eigen::Vector3d& n) {
    e->px[i] = n.x();
    e->py[i] = n.y();
    e->pz[i] = n.z();
    e->pr[i] = supportOf(*e->shape, n);
  };
  for (std::size_t i = 0; i < axes.size(); ++i) put(static_cast<int>(i), axes[i]);
  for (std::size_t i = 0; i < spread.size(); ++i)
    put(e->node_planes + static_cast<int>(i), spread[i]);
  const std::vector<int> order = groupFaceNormals(faces);
  for (std::size_t i = 0; i < faces.size(); ++i)
    put(e->facet_begin + static_cast<int>(i), faces[static_cast<std::size_t>(order[i])]);
  addFaceBlocks(order, e);
}

void buildCulling(const std::vector<Eigen::Vector3d>& vertices,
                  const std::vector<Eigen::Vector3i>& faces, bool all_shapes,
                  CollisionScene::Data* d) {
  d->culled_boxes = all_shapes;
  d->corners.resize(faces.size());
  for (std::size_t t = 0; t < faces.size(); ++t)
    for (int k = 0; k < 3; ++k)
      d->corners[t][static_cast<std::size_t>(k)] = vertices[static_cast<std::size_t>(faces[t][k])];
  btOptimizedBvh* bvh = d->mesh_shape->getOptimizedBvh();
  // Without a quantized tree (not built by this constructor) the queries stay on Bullet's path.
  d->culled = bvh != nullptr && bvh->isQuantized();
  if (!d->culled) return;
  const auto& nodes = bvh->getQuantizedNodeArray();
  d->node_boxes.resize(static_cast<std::size_t>(nodes.size()));
  for (int i = 0; i < nodes.size(); ++i)
    d->node_boxes[static_cast<std::size_t>(i)] = {
        eig(bvh->unQuantize(nodes[i].m_quantizedAabbMin)),
        eig(bvh->unQuantize(nodes[i].m_quantizedAabbMax))};
  buildNormalCones(d);
}

namespace {

/// The smallest cone holding cones a and b, widened by 1e-9 rad against rounding.
CollisionScene::Data::NormalCone mergeCones(const CollisionScene::Data::NormalCone& a,
                                            const CollisionScene::Data::NormalCone& b) {
  const double theta = std::acos(std::clamp(a.axis.dot(b.axis), -1.0, 1.0));
  if (theta + b.half <= a.half) return a;  // b inside a
  if (theta + a.half <= b.half) return b;
  CollisionScene::Data::NormalCone c;
  c.half = 0.5 * (theta + a.half + b.half) + 1e-9;
  if (c.half >= kPi || theta > kPi - 1e-6) {
    c.half = kPi;
    return c;
  }
  // Turn a's axis toward b's by c.half - a.half (within the plane of both axes).
  const double t = c.half - a.half;
  const Eigen::Vector3d side = (b.axis - a.axis * std::cos(theta)).normalized();
  c.axis = (a.axis * std::cos(t) + side * std::sin(t)).normalized();
  return c;
}

}  // namespace

void buildNormalCones(CollisionScene::Data* d) {
  const auto& nodes = d->mesh_shape->getOptimizedBvh()->getQuantizedNodeArray();
  d->node_cones.assign(static_cast<std::size_t>(nodes.size()), {});
  // Children follow their parent in the array: the last node first.
  for (int i = nodes.size() - 1; i >= 0; --i) {
    auto& cone = d->node_cones[static_cast<std::size_t>(i)];
    if (nodes[i].isLeafNode()) {
      cone.axis = d->normals[static_cast<std::size_t>(nodes[i].getTriangleIndex())];
      continue;
    }
    const int left = i + 1;
    const int right = left + (nodes[left].isLeafNode() ? 1 : nodes[left].getEscapeIndex());
    cone = mergeCones(d->node_cones[static_cast<std::size_t>(left)],
                      d->node_cones[static_cast<std::size_t>(right)]);
  }
  for (auto& cone : d->node_cones) {
    cone.cos_half = std::cos(cone.half);
    cone.sin_half = std::sin(cone.half);
  }
}

namespace {

/// The baseline's loop with culling: every triangle the planes keep, in Bullet's order (stops
/// at the first overlap unless q is exact).
void walkAll(const CollisionScene::Data& d, const ShapePlanes& pl, TriangleQuery* q) {
  // Hull contacts (sat_depths): the face planes' penetration where they prove it.
  const bool hull_faces = q->sat_depths && q->exact && !q->is_box && pl.facet_begin < pl.count;
  walkInBulletOrder(
      d, [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) { return pl.node(lo, hi); },
      [&](int tri) {
        const auto& v = d.corners[static_cast<std::size_t>(tri)];
        // Hull contacts: the planes before the faces, then the faces (the tight bound's
        // decision), whose products the face contact reads.
        if (pl.bound(v, pl.cut, q->exact && !hull_faces) > pl.cut) return true;
        int face = -1;
        const double g = hull_faces ? pl.faceGap(v, pl.cut, &face) : 0.0;
        if (hull_faces && g > pl.cut) return true;
        TriangleHit h;
        double depth = 0.0;
        if (hull_faces && pl.faceContact(v, g, face, kSatDepthMin, &depth, &h.normal, &h.point)) {
          h.distance = -depth;
          h.triangle = tri;
          q->min_distance = std::min(q->min_distance, h.distance);
          if (q->hits) q->hits->push_back(h);
        } else {
          runTriangle(d, tri, q);
        }
        return q->exact || !q->overlap_found;
      });
}

/// Skips a box triangle whose 13-axis gap exceeds the best distance (GJK could not beat it).
bool boxBeyond(const CollisionScene::Data& d, int tri, const TriangleQuery& q) {
  if (!q.is_box || q.min_distance == kInf) return false;
  const auto& v = d.corners[static_cast<std::size_t>(tri)];
  const btVector3 corners[3] = {bt(v[0]), bt(v[1]), bt(v[2])};
  const double limit = q.min_distance + kCullSlack;
  return boxTriangleSeparation(q.box_centre, q.box_axes, q.box_half, corners, limit) > limit;
}

/// No overlap: the minimum of GJK distances does not depend on the order, so the tree is
/// searched depth first, nearer child first by the planes' bound, skipping every node whose
/// bound exceeds the best distance found (GJK distances are upper bounds of the true ones:
/// nothing there could be smaller).
void branchAndBound(const CollisionScene::Data& d, const ShapePlanes& pl, TriangleQuery* q) {
  walkNearestFirst(
      d, pl, [q] { return q->min_distance; }, [q] { return q->overlap_found; },
      [&](int tri, double, int) {
        if (!boxBeyond(d, tri, *q)) runTriangle(d, tri, q);
      });
}

/// Overlap query of a hull (distances >= 0 unless overlapping): a proof of overlap, a triangle
/// corner 1e-6 m inside every face plane, is the answer (the baseline reports kOverlapping for
/// whichever overlapping triangle it meets first; hull margins are 0, so GJK never returns a
/// negative distance), and without one the answer is branchAndBound's: one nearest-first walk
/// does both. A leaf with bound <= 0 is first tried for a proof, else it goes to GJK as in
/// branchAndBound (an overlap GJK reports ends the walk with kOverlapping too). Deep nodes come
/// first, where a proof lies. (This differs from the baseline only where Bullet's GJK finds no
/// overlap on a triangle with a corner inside the hull; the proof is then the right answer.)
void hullOverlapQuery(const CollisionScene::Data& d, const ShapePlanes& pl, TriangleQuery* q) {
  walkNearestFirst(
      d, pl, [q] { return q->min_distance; }, [q] { return q->overlap_found; },
      [&](int tri, double lb, int) {
        const auto& v = d.corners[static_cast<std::size_t>(tri)];
        // The face planes before GJK: a triangle they put beyond the walk's limit has no corner
        // inside and a GJK distance above the limit (no answer changes).
        const double limit = std::min(pl.cut, q->min_distance + kCullSlack);
        int face = -1;
        if (pl.faceGap(v, limit, &face) > limit) return;
        if (lb <= 0.0 && (pl.insideFaces(v, 0) || pl.insideFaces(v, 1) || pl.insideFaces(v, 2))) {
          q->overlap_found = true;
          q->min_distance = kOverlapping;
          return;
        }
        runTriangle(d, tri, q);
      });
}

/// Overlap query of a box within a small threshold (<= kOneWalkThreshold), in one walk in
/// Bullet's order with the baseline's own tests (planes at the threshold, then the 13-axis gap
/// g): a triangle with g <= 0 is the baseline's first overlap unless GJK, which the baseline runs
/// on the triangles before it with 0 < g <= threshold, reports one there; so those (kept in
/// order) and then it go through the TriangleQuery, as in the baseline's loop. Without such a
/// triangle the kept ones are all the baseline runs GJK on: their minimum distance is found
/// nearest gap first, stopping where the gap exceeds the best distance (GJK distances are >= the
/// gap).
/// With `seen`, the kept triangles of a walk without a proof are recorded (by gap).
void boxOverlapQuery(const CollisionScene::Data& d, const ShapePlanes& pl, TriangleQuery* q,
                     SeenTriangles* seen) {
  thread_local std::vector<std::tuple<double, int, int>> kept;  // (gap, triangle, leaf node)
  kept.clear();
  int proof = -1;
  walkInBulletOrder(
      d, [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) { return pl.node(lo, hi); },
      [&](int tri, int node) {
        const auto& v = d.corners[static_cast<std::size_t>(tri)];
        if (pl.bound(v) > pl.cut) return true;
        const btVector3 corners[3] = {bt(v[0]), bt(v[1]), bt(v[2])};
        const double gap =
            boxTriangleSeparation(q->box_centre, q->box_axes, q->box_half, corners, q->threshold);
        if (gap > q->threshold) return true;
        if (gap <= 0.0) {
          proof = tri;
          return false;
        }
        kept.emplace_back(gap, tri, node);  // Bullet's order
        return true;
      });
  if (proof >= 0) {
    for (const auto& k : kept) runTriangle(d, std::get<1>(k), q);  // no-op after an overlap
    runTriangle(d, proof, q);
    return;
  }
  std::sort(kept.begin(), kept.end());  // by gap, then triangle (each in one leaf)
  if (seen) {
    seen->near.clear();
    for (const auto& [gap, tri, node] : kept) seen->near.push_back({gap, tri, node});
    seen->complete = true;
  }
  for (const auto& [gap, tri, node] : kept) {
    if (q->overlap_found || gap > q->min_distance + kCullSlack) break;
    runTriangle(d, tri, q);
  }
}

/// Overlap query of a box beyond kOneWalkThreshold (distances >= 0 unless overlapping). These
/// are mostly asked of free poses (conservative advancement), so branchAndBound goes first: if
/// it meets no overlap, no triangle has a separating-axis gap <= 0 (such a triangle's bound is
/// <= 0, below every limit the search prunes at, so the search reaches it unless an overlap
/// stops it first), and its nearest distance is the answer. Otherwise the tree is walked in
/// Bullet's order for a proof of overlap, visiting only what the planes do not put beyond
/// contact: a triangle whose gap is <= 0. The baseline stops at its first overlap in the same
/// order, which is the first triangle with gap <= 0 (it reports min(gap, kOverlapping), the
/// same test), unless GJK reports one on a triangle before it: so a proof runs the baseline's
/// loop (walkAll, which stops at the first overlap). Without a proof (GJK alone reported the
/// overlap) branchAndBound's answer stands.
void boxProofQuery(const CollisionScene::Data& d, const ShapePlanes& pl, TriangleQuery* q) {
  TriangleQuery free = *q;
  branchAndBound(d, pl, &free);
  if (!free.overlap_found) {
    *q = free;
    return;
  }
  bool proven = false;
  walkInBulletOrder(
      d,
      [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
        return pl.nodeBound(lo, hi, kCullSlack) <= kCullSlack;
      },
      [&](int tri) {
        const auto& v = d.corners[static_cast<std::size_t>(tri)];
        if (pl.bound(v, 0.0) > 0.0) return true;  // a face plane separates: no overlap
        const btVector3 corners[3] = {bt(v[0]), bt(v[1]), bt(v[2])};
        proven =
            boxTriangleSeparation(q->box_centre, q->box_axes, q->box_half, corners, 0.0) <= 0.0;
        return !proven;
      });
  if (proven)
    walkAll(d, pl, q);
  else
    *q = free;
}

}  // namespace

double queryLinkCulled(const CollisionScene::Data& d, const std::vector<ShapeEntry>& entries,
                       const Eigen::Isometry3d& t, double threshold, bool exact,
                       std::vector<TriangleHit>* hits, bool sat_depths, SeenTriangles* seen) {
  thread_local ShapePlanes pl;
  if (seen) {
    seen->complete = false;
    seen->link = -1;
    seen->pose = t;
    seen->threshold = threshold;
    if (entries.size() != 1 || !entries[0].is_box || !d.culled_boxes || exact ||
        threshold > kOneWalkThreshold)
      seen = nullptr;  // only a link of one box's overlap walk is recorded
  }
  double best = kInf;
  for (const ShapeEntry& e : entries) {
    const Eigen::Isometry3d ts = t * e.origin;
    if (beyondObjectBox(d, e, ts, threshold)) {
      if (seen) {  // nothing within reach
        seen->near.clear();
        seen->complete = true;
      }
      continue;
    }
    if (!e.is_hull && !d.culled_boxes) {
      best = std::min(best, queryShapeBullet(d, e, ts, threshold, exact, hits));
      if (!exact && best < 0.0) break;
      continue;
    }
    TriangleQuery q = makeTriangleQuery(e, ts, threshold, exact, hits);
    q.sat_depths = sat_depths && e.sat_depths;
    btVector3 amin, amax;
    e.shape->getAabb(q.xf, amin, amax);
    pl.set(e, ts, amin, amax, threshold);
    if (!exact && e.is_box && threshold <= kOneWalkThreshold) {
      boxOverlapQuery(d, pl, &q, seen);
    } else if (!exact && e.is_box) {
      boxProofQuery(d, pl, &q);
    } else if (!exact && e.is_hull) {
      hullOverlapQuery(d, pl, &q);
    } else {
      // Exact hits (in Bullet's order), and spheres and cylinders as the baseline runs them.
      walkAll(d, pl, &q);
    }
    best = std::min(best, q.min_distance);
    if (!exact && best < 0.0) break;
  }
  return best;
}

}  // namespace taskmap
