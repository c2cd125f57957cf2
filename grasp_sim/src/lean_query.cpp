// Lean exact queries: questions the trial asks of the exact hits (linkHits) answered without
// computing every hit, with the same answer bit for bit (docs/METHOD.md §2):
//   CollisionScene::linkPressesDeeper  is some facing triangle penetrated deeper than a depth?
//   CollisionScene::linkNearest        the smallest signed distance over the hits that pass a
//                                      facing filter (or over all hits).
// and, on the same tree walk, CollisionScene::linkSweepLast and linkSweepClear: from where on
// does a link moved along a line provably stay beyond a gap (a conservative bound)?
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "collision_data.hpp"
#include "culled_planes.hpp"

namespace taskmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// linkSweepLast: the swept length beyond the reach of the object's sphere, metres (far above
/// rounding; beyond that length the link box is farther than the gap from the object's box).
constexpr double kSweepBeyond = 0.01;

/// The points c + u dir, u in [0, len], that meet the box [lo, hi] (slabs; a component of dir
/// that is zero keeps c's coordinate): the largest such u, or -1 when none does.
double rayLastInBox(const Eigen::Vector3d& c, const Eigen::Vector3d& dir, double len,
                    const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  double u0 = 0.0, u1 = len;
  for (int i = 0; i < 3; ++i) {
    if (dir[i] == 0.0) {
      if (c[i] < lo[i] || c[i] > hi[i]) return -1.0;
      continue;
    }
    double ua = (lo[i] - c[i]) / dir[i], ub = (hi[i] - c[i]) / dir[i];
    if (ua > ub) std::swap(ua, ub);
    u0 = std::max(u0, ua);
    u1 = std::min(u1, ub);
    if (u0 > u1) return -1.0;
  }
  return u1;
}

/// A link box (centre c, axes the columns of R, half extents h; object frame) grown by a ball of
/// radius gap and moved along d by u in [0, len]: its extent along 6 axes (the box's three, and
/// each crossed with d; the object's axes are the centre line's test, the nine crossings of box
/// and object axes cost more than they prune), for a separating-axis bound against
/// axis-aligned boxes and triangles. On each axis the moved box's extent overlaps the other set's
/// only for u in an interval; outside the intersection of those intervals some axis separates
/// the two, so the link is farther than gap (whichever axes are tried: the bound can only be
/// loose, never too small).
class SweptBox {
 public:
  SweptBox(const Eigen::Vector3d& c, const Eigen::Matrix3d& r, const Eigen::Vector3d& h,
           const Eigen::Vector3d& d, double len, double gap)
      : c_(c), r_(r), h_(h), d_(d), len_(len), gap_(gap) {
    int k = 0;
    for (int j = 0; j < 3; ++j) n_.col(k++) = r.col(j);
    for (int j = 0; j < 3; ++j) n_.col(k++) = d.cross(r.col(j));
    for (int a = 0; a < kAxes; ++a) extent(n_.col(a), &ax_[a]);
    abs_ = n_.cwiseAbs();
  }
  /// The largest u at which the moved box may meet the box [lo, hi]; -1 when it never does.
  double last(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) const {
    const Eigen::Vector3d bc = 0.5 * (lo + hi), bh = 0.5 * (hi - lo);
    double u0 = 0.0, u1 = len_;
    for (int a = 0; a < kAxes; ++a) {
      const double p = n_.col(a).dot(bc), r = abs_.col(a).dot(bh);
      if (!narrow(ax_[a], p - r, p + r, &u0, &u1)) return -1.0;
    }
    return u1;
  }
  /// The same for the triangle with corners v (the 6 axes and the triangle's normal).
  double last(const std::array<Eigen::Vector3d, 3>& v, const Eigen::Vector3d& normal) const {
    double u0 = 0.0, u1 = len_;
    for (int a = 0; a < kAxes; ++a)
      if (!narrowTriangle(n_.col(a), ax_[a], v, &u0, &u1)) return -1.0;
    Axis na;
    extent(normal, &na);
    return narrowTriangle(normal, na, v, &u0, &u1) ? u1 : -1.0;
  }

 private:
  static constexpr int kAxes = 6;
  struct Axis {
    double lo = 0.0, hi = 0.0, nd = 0.0;  // the grown box's extent at u = 0; n . d
  };
  void extent(const Eigen::Vector3d& n, Axis* out) const {
    const double mid = n.dot(c_), ext = (r_.transpose() * n).cwiseAbs().dot(h_) + gap_ * n.norm();
    out->lo = mid - ext;
    out->hi = mid + ext;
    out->nd = n.dot(d_);
  }
  // Narrows [u0, u1] to the u at which [ax.lo, ax.hi] + u nd meets [blo, bhi]; false if empty.
  static bool narrow(const Axis& ax, double blo, double bhi, double* u0, double* u1) {
    const double x = blo - ax.hi, y = bhi - ax.lo;  // overlap iff x <= u nd <= y
    if (ax.nd == 0.0) return x <= 0.0 && 0.0 <= y;
    double ua = x / ax.nd, ub = y / ax.nd;
    if (ua > ub) std::swap(ua, ub);
    *u0 = std::max(*u0, ua);
    *u1 = std::min(*u1, ub);
    return *u0 <= *u1;
  }
  static bool narrowTriangle(const Eigen::Vector3d& n, const Axis& ax,
                             const std::array<Eigen::Vector3d, 3>& v, double* u0, double* u1) {
    const double p0 = n.dot(v[0]), p1 = n.dot(v[1]), p2 = n.dot(v[2]);
    return narrow(ax, std::min({p0, p1, p2}), std::max({p0, p1, p2}), u0, u1);
  }
  Eigen::Vector3d c_;
  Eigen::Matrix3d r_;
  Eigen::Vector3d h_, d_;
  double len_, gap_;
  Eigen::Matrix<double, 3, kAxes> n_, abs_;
  std::array<Axis, kAxes> ax_{};
};

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
      d,
      [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
        return pl.nodeBound(lo, hi, c) <= c;
      },
      [&](int tri) {
        const auto& v = d.corners[static_cast<std::size_t>(tri)];
        if (pl.bound(v, c) > c) return true;
        if (e.is_box) {
          const btVector3 corners[3] = {bt(v[0]), bt(v[1]), bt(v[2])};
          if (boxTriangleSeparation(q.box_centre, q.box_axes, q.box_half, corners, c) > c)
            return true;
        }
        hits.clear();
        runTriangle(d, tri, &q);
        found = deepFacing(d, hits, depth, min_agreement);
        return !found;
      });
  return found;
}

bool passes(const CollisionScene::Data& d, const TriangleHit& h, const FacingFilter* f) {
  return !f || f->passes(d.normals[static_cast<std::size_t>(h.triangle)], h);
}

/// The best hit so far of queryLinkNearest: its distance and, when wanted, the hit and its place
/// in the baseline's order (shape index, then Bullet's leaf order, which is node order).
struct NearestHit {
  double distance = kInf;
  TriangleHit* hit = nullptr;
  std::pair<int, int> key{-1, -1};

  void offer(const TriangleHit& h, std::pair<int, int> k) {
    if (h.distance < distance || (hit && h.distance == distance && k < key)) {
      distance = h.distance;
      key = k;
      if (hit) *hit = h;
    }
  }
};

/// One shape of queryLinkNearest: depth-first branch and bound over Bullet's tree, nearer child
/// first by the planes' bound; a node or triangle whose bound exceeds the best distance found is
/// skipped. Every signed distance GJK/EPA reports is >= the bound (a separation is >= the true
/// distance; an EPA depth is <= the true penetration depth, itself <= the overlap along any
/// plane normal), so nothing skipped could be smaller, nor tie (the bound is compared with the
/// best + 1e-9 m).
void nearestOfShape(const CollisionScene::Data& d, const ShapeEntry& e, const Eigen::Isometry3d& ts,
                    double threshold, const FacingFilter* f, int shape, NearestHit* best) {
  thread_local ShapePlanes pl;
  thread_local std::vector<TriangleHit> hits;
  TriangleQuery q = makeTriangleQuery(e, ts, threshold, true, &hits);
  btVector3 amin, amax;
  e.shape->getAabb(q.xf, amin, amax);
  pl.set(e, ts, amin, amax, threshold);
  // Triangles whose normal does not oppose the shift are dropped before their bound.
  auto facing = [&](int tri) { return !f || f->faces(d.normals[static_cast<std::size_t>(tri)]); };
  // Subtrees whose normals all lie acos(opposing) or more from -away hold no such triangle.
  const bool filtered = f && !f->any_direction;
  const NormalFilter normals(filtered ? Eigen::Vector3d(-f->away) : Eigen::Vector3d::UnitZ(),
                             filtered ? f->opposing : -1.0);
  walkNearestFirst(
      d, pl, [best] { return best->distance; }, [] { return false; }, facing,
      filtered ? &normals : nullptr,
      [&](int tri, double, int node) {
        const auto& v = d.corners[static_cast<std::size_t>(tri)];
        if (e.is_box) {
          const btVector3 corners[3] = {bt(v[0]), bt(v[1]), bt(v[2])};
          const double limit = best->distance + kCullSlack;
          if (boxTriangleSeparation(q.box_centre, q.box_axes, q.box_half, corners, limit) > limit)
            return;
        } else if (e.is_hull) {
          // The hull's face planes before GJK/EPA (their gap is a lower bound of its distance).
          const double limit = std::min(pl.cut, best->distance + kCullSlack);
          int face = -1;
          if (pl.faceGap(v, limit, &face) > limit) return;
        }
        hits.clear();
        runTriangle(d, tri, &q);
        for (const TriangleHit& h : hits)
          if (passes(d, h, f)) best->offer(h, {shape, node});
      });
}

}  // namespace

double queryLinkNearest(const CollisionScene::Data& d, const std::vector<ShapeEntry>& entries,
                        const Eigen::Isometry3d& t, double threshold, const FacingFilter* f,
                        TriangleHit* hit) {
  NearestHit best;
  best.hit = hit;
  for (std::size_t s = 0; s < entries.size(); ++s) {
    const ShapeEntry& e = entries[s];
    const Eigen::Isometry3d ts = t * e.origin;
    if (beyondObjectBox(d, e, ts, threshold)) continue;  // the baseline's cull
    if (d.culled) {
      nearestOfShape(d, e, ts, threshold, f, static_cast<int>(s), &best);
    } else {
      thread_local std::vector<TriangleHit> hits;
      hits.clear();
      queryShapeBullet(d, e, ts, threshold, true, &hits);
      for (std::size_t k = 0; k < hits.size(); ++k)
        if (passes(d, hits[k], f)) best.offer(hits[k], {static_cast<int>(s), static_cast<int>(k)});
    }
  }
  return best.distance;
}

// The triangles nearestOfShape could report are within the threshold by their gap, so among
// `seen`; by gap order, a triangle whose gap exceeds the best distance + 1e-9 m ends the scan
// (GJK's distance is at least the gap; the rest lie farther), as it is skipped there; the rest
// go through the same exact TriangleQuery, and the best is kept with the same key.
double queryLinkNearestSeen(const CollisionScene::Data& d, const ShapeEntry& e,
                            const Eigen::Isometry3d& ts, double threshold, const FacingFilter* f,
                            TriangleHit* hit, const SeenTriangles& seen) {
  NearestHit best;
  best.hit = hit;
  thread_local std::vector<TriangleHit> hits;
  TriangleQuery q = makeTriangleQuery(e, ts, threshold, true, &hits);
  for (const SeenTriangles::Near& n : seen.near) {
    if (n.gap > best.distance + kCullSlack) break;
    if (f && !f->faces(d.normals[static_cast<std::size_t>(n.triangle)])) continue;
    hits.clear();
    runTriangle(d, n.triangle, &q);
    for (const TriangleHit& h : hits)
      if (passes(d, h, f)) best.offer(h, {0, n.node});
  }
  return best.distance;
}

bool queryLinkDeeper(const CollisionScene::Data& d, const std::vector<ShapeEntry>& entries,
                     const Eigen::Isometry3d& t, double threshold, double depth,
                     double min_agreement) {
  for (const ShapeEntry& e : entries) {
    const Eigen::Isometry3d ts = t * e.origin;
    if (beyondObjectBox(d, e, ts, threshold)) continue;  // the baseline's cull
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

// Each box of the object's tree (and each triangle) is bounded twice: the line of the link box's
// centre against it grown on every axis by the link box's extent along it plus the gap (the link
// box lies within its centre plus that extent; the object within its box, each triangle within
// its node's and its own box), and the link box itself swept (SweptBox); the smaller last u of
// the two holds. The sweep is cut at the length beyond which the link box cannot come within
// the gap of the object's sphere. A box whose bound is no later than the latest found so far is
// skipped; with `first` the walk ends at the first triangle the link may meet.
double CollisionScene::linkSweepLast(int link, const Eigen::Isometry3d& t,
                                     const Eigen::Vector3d& dir, double gap, bool first) const {
  const Data& d = *d_;
  const auto& box = d.link_box[static_cast<std::size_t>(link)];
  const Eigen::Vector3d c = t * box[0];
  const Eigen::Vector3d r = t.linear().cwiseAbs() * box[1] + Eigen::Vector3d::Constant(gap);
  const double len = (c - d.centre).norm() + d.radius + box[1].norm() + gap + kSweepBeyond;
  double best = rayLastInBox(c, dir, len, d.lo - r, d.hi + r);
  if (best < 0.0) return -1.0;
  if (!d.culled) return len;
  const SweptBox swept(c, t.linear(), box[1], dir, len, gap);
  best = std::min(best, swept.last(d.lo, d.hi));
  if (best < 0.0) return -1.0;
  best = -1.0;
  walkInBulletOrder(
      d,
      [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
        return rayLastInBox(c, dir, len, lo - r, hi + r) > best && swept.last(lo, hi) > best;
      },
      [&](int tri) {
        const auto& v = d.corners[static_cast<std::size_t>(tri)];
        const Eigen::Vector3d lo = v[0].cwiseMin(v[1]).cwiseMin(v[2]);
        const Eigen::Vector3d hi = v[0].cwiseMax(v[1]).cwiseMax(v[2]);
        const double ray = rayLastInBox(c, dir, len, lo - r, hi + r);
        if (ray <= best) return true;
        best =
            std::max(best, std::min(ray, swept.last(v, d.normals[static_cast<std::size_t>(tri)])));
        return !(first && best >= 0.0);
      });
  return best;
}

bool CollisionScene::linkSweepClear(int link, const Eigen::Isometry3d& t,
                                    const Eigen::Vector3d& dir, double gap) const {
  return linkSweepLast(link, t, dir, gap, true) < 0.0;
}

}  // namespace taskmap
