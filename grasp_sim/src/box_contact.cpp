// The penetration of an oriented box and a triangle from the 13 separating axes (declared in
// collision_data.hpp; the equations are in docs/METHOD.md §2, "Contacts from separating axes").
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "collision_data.hpp"

namespace taskmap {
namespace {

/// Features whose levels along the contact normal differ by at most this much tie, metres: the
/// witness is then the centre of the overlap of the two features, not one corner of it.
constexpr double kTie = 1e-9;
/// A later axis replaces the best one only when it separates more by this much, metres: at a
/// tie the box face, then the triangle's normal, is the axis (an edge pair parallel to a face
/// gives the face's direction, but its witness would assume the edges are the deepest features).
constexpr double kAxisTie = 1e-12;
/// Axes shorter than this are skipped (parallel edges), as in boxTriangleSeparation.
constexpr double kMinAxis = 1e-12;

/// A convex polygon (or segment, or point) of at most 12 corners, box frame.
struct Feature {
  std::array<Eigen::Vector3d, 12> p;
  int n = 0;
  void add(const Eigen::Vector3d& x) { p[static_cast<std::size_t>(n++)] = x; }
  Eigen::Vector3d centre() const {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (int i = 0; i < n; ++i) s += p[static_cast<std::size_t>(i)];
    return s / static_cast<double>(n);
  }
};

/// The half space m . x <= h.
struct Plane {
  Eigen::Vector3d m;
  double h;
};

/// Keeps the part of `f` where m . x <= h: Sutherland-Hodgman for polygons, the parameter
/// interval for a segment; a point is kept or dropped.
Feature clip(const Feature& f, const Eigen::Vector3d& m, double h) {
  Feature out;
  if (f.n <= 2) {
    const Eigen::Vector3d& a = f.p[0];
    const Eigen::Vector3d& b = f.p[static_cast<std::size_t>(f.n - 1)];
    const double da = m.dot(a) - h, db = m.dot(b) - h;
    if (da > 0.0 && db > 0.0) return out;
    if (f.n == 1 || (da <= 0.0 && db <= 0.0)) return f;
    const Eigen::Vector3d x = a + (b - a) * (da / (da - db));
    out.add(da <= 0.0 ? a : x);
    out.add(da <= 0.0 ? x : b);
    return out;
  }
  for (int i = 0; i < f.n; ++i) {
    const Eigen::Vector3d& a = f.p[static_cast<std::size_t>(i)];
    const Eigen::Vector3d& b = f.p[static_cast<std::size_t>((i + 1) % f.n)];
    const double da = m.dot(a) - h, db = m.dot(b) - h;
    if (da <= 0.0) out.add(a);
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) out.add(a + (b - a) * (da / (da - db)));
  }
  return out;
}

/// The centre of `f` clipped by every plane of `planes` (m, h), or of `f` itself when rounding
/// leaves nothing (the clip region then touches `f` only at its border). A point is its own
/// centre either way.
Eigen::Vector3d clippedCentre(const Feature& f, const Plane* planes, int count) {
  if (f.n == 1) return f.p[0];
  Feature g = f;
  for (int k = 0; k < count && g.n > 0; ++k) g = clip(g, planes[k].m, planes[k].h);
  return g.n > 0 ? g.centre() : f.centre();
}

/// The point of segment [p, p + s] closest to segment [q, q + t] (Ericson, Real-Time Collision
/// Detection 5.1.9), for non-parallel segments.
Eigen::Vector3d closestOnSecond(const Eigen::Vector3d& p, const Eigen::Vector3d& s,
                                const Eigen::Vector3d& q, const Eigen::Vector3d& t) {
  const Eigen::Vector3d r = p - q;
  const double a = s.dot(s), e = t.dot(t), f = t.dot(r), c = s.dot(r), b = s.dot(t);
  const double denom = a * e - b * b;
  const double x = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  // Where the clamp of y to [0, 1] moves it, x would be re-clamped: y does not change.
  const double y = std::clamp((b * x + f) / e, 0.0, 1.0);
  return q + t * y;
}

/// Witness of a box face axis (u = +-e_i, box frame): the triangle's deepest feature along -u,
/// within the face's side planes.
Eigen::Vector3d faceWitness(const Eigen::Vector3d* v, const Eigen::Vector3d& u, int i,
                            const Eigen::Vector3d& half) {
  const double lo = std::min({u.dot(v[0]), u.dot(v[1]), u.dot(v[2])});
  Feature f;
  for (int k = 0; k < 3; ++k)
    if (u.dot(v[k]) <= lo + kTie) f.add(v[k]);
  Plane sides[4];
  int n = 0;
  for (int j = 0; j < 3; ++j) {
    if (j == i) continue;
    sides[n++] = {Eigen::Vector3d::Unit(j), half[j]};
    sides[n++] = {-Eigen::Vector3d::Unit(j), half[j]};
  }
  return clippedCentre(f, sides, n);
}

/// Witness of the triangle's normal axis: the box's deepest feature along +u moved onto the
/// triangle's plane (by `depth` along -u), within the triangle's edges.
Eigen::Vector3d triangleWitness(const Eigen::Vector3d* v, const Eigen::Vector3d& u, double depth,
                                const Eigen::Vector3d& half) {
  Eigen::Vector3d corner;
  int free_axes[2];
  int nfree = 0;
  for (int j = 0; j < 3; ++j) {
    if (2.0 * half[j] * std::abs(u[j]) <= kTie && nfree < 2) {
      corner[j] = 0.0;
      free_axes[nfree++] = j;
    } else {
      corner[j] = u[j] > 0.0 ? half[j] : -half[j];
    }
  }
  Feature f;
  const Eigen::Vector3d shift = corner - depth * u;
  if (nfree == 0) {
    f.add(shift);
  } else if (nfree == 1) {
    const Eigen::Vector3d d = half[free_axes[0]] * Eigen::Vector3d::Unit(free_axes[0]);
    f.add(shift - d);
    f.add(shift + d);
  } else {
    const Eigen::Vector3d da = half[free_axes[0]] * Eigen::Vector3d::Unit(free_axes[0]);
    const Eigen::Vector3d db = half[free_axes[1]] * Eigen::Vector3d::Unit(free_axes[1]);
    f.add(shift - da - db);
    f.add(shift + da - db);
    f.add(shift + da + db);
    f.add(shift - da + db);
  }
  const Eigen::Vector3d normal = (v[1] - v[0]).cross(v[2] - v[0]);
  Plane edges[3];
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d out = (v[(k + 1) % 3] - v[k]).cross(normal);
    edges[k] = {out, out.dot(v[k])};
  }
  return clippedCentre(f, edges, 3);
}

}  // namespace

BoxTrianglePenetration boxTrianglePenetration(const Eigen::Vector3d& c, const Eigen::Matrix3d& r,
                                              const Eigen::Vector3d& e, const btVector3* tri) {
  Eigen::Vector3d v[3];
  for (int i = 0; i < 3; ++i)
    v[i] = r.transpose() * (Eigen::Vector3d(tri[i].x(), tri[i].y(), tri[i].z()) - c);
  const Eigen::Vector3d f[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  // The axis of largest separation (smallest overlap), u from the box toward the triangle;
  // kind 0..2 a box face, 3 the triangle's normal, 4 + 3 j + i box axis i x triangle edge j.
  double best = -std::numeric_limits<double>::infinity();
  double sep = best;  // the plain maximum, as boxTriangleSeparation computes it
  Eigen::Vector3d u = Eigen::Vector3d::UnitZ();
  int kind = -1;
  auto axis = [&](const Eigen::Vector3d& l, int k) {
    const double len = l.norm();
    if (len < kMinAxis) return;
    const double p0 = l.dot(v[0]), p1 = l.dot(v[1]), p2 = l.dot(v[2]);
    const double rad = e.x() * std::abs(l.x()) + e.y() * std::abs(l.y()) + e.z() * std::abs(l.z());
    const double above = (std::min({p0, p1, p2}) - rad) / len;
    const double below = (-rad - std::max({p0, p1, p2})) / len;
    const double s = std::max(above, below);
    sep = std::max(sep, s);
    if (s > best + kAxisTie) {
      best = s;
      u = (above >= below ? l : Eigen::Vector3d(-l)) / len;
      kind = k;
    }
  };
  // The box's own axes written out (unit axes: the dot products are coordinates, the norm 1,
  // so the lambda's arithmetic gives the same numbers).
  for (int i = 0; i < 3; ++i) {
    const double above = std::min({v[0][i], v[1][i], v[2][i]}) - e[i];
    const double below = -e[i] - std::max({v[0][i], v[1][i], v[2][i]});
    const double s = std::max(above, below);
    sep = std::max(sep, s);
    if (s > best + kAxisTie) {
      best = s;
      u = above >= below ? Eigen::Vector3d::Unit(i) : Eigen::Vector3d(-Eigen::Vector3d::Unit(i));
      kind = i;
    }
  }
  axis(f[0].cross(f[1]), 3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) axis(Eigen::Vector3d::Unit(i).cross(f[j]), 4 + 3 * j + i);

  BoxTrianglePenetration out;
  out.separation = sep;
  out.depth = -best;
  if (!(sep < 0.0)) return out;
  Eigen::Vector3d w;
  if (kind < 0) {  // a degenerate triangle: no axis
    w = (v[0] + v[1] + v[2]) / 3.0;
  } else if (kind < 3) {
    w = faceWitness(v, u, kind, e);
  } else if (kind == 3) {
    w = triangleWitness(v, u, out.depth, e);
  } else {
    const int j = (kind - 4) / 3, i = (kind - 4) % 3;
    Eigen::Vector3d edge_mid;
    for (int k = 0; k < 3; ++k) edge_mid[k] = k == i ? 0.0 : (u[k] > 0.0 ? e[k] : -e[k]);
    const Eigen::Vector3d along = e[i] * Eigen::Vector3d::Unit(i);
    w = closestOnSecond(edge_mid - along, 2.0 * along, v[j], f[j]);
  }
  out.point = c + r * w;
  out.normal = -(r * u);
  return out;
}

}  // namespace taskmap
