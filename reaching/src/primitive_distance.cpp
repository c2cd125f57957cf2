// Segment-segment, segment-rectangle and rectangle-rectangle closest points; the sweep radii
// are subtracted afterwards (docs/REACHING.md, "Collision primitives").
#include "taskmap/reaching/primitive_distance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace taskmap {
namespace {

/// A core in world coordinates: centre, axes, half extents (hv = 0 for a segment).
struct Core {
  Eigen::Vector3d c, u, v, n;
  double hu = 0.0, hv = 0.0;
  bool rect = false;
};

Core worldCore(const Primitive& p, const Eigen::Isometry3d& pose) {
  Core k;
  k.c = pose * p.center;
  const Eigen::Matrix3d axes = pose.linear() * p.axes;
  k.u = axes.col(0);
  k.v = axes.col(1);
  k.n = axes.col(2);
  k.hu = p.half_u;
  k.hv = p.type == PrimitiveType::kSweptRectangle ? p.half_v : 0.0;
  k.rect = p.type == PrimitiveType::kSweptRectangle;
  return k;
}

struct Candidate {
  double d2 = std::numeric_limits<double>::infinity();
  Eigen::Vector3d a, b;
  void offer(const Eigen::Vector3d& pa, const Eigen::Vector3d& pb) {
    const double d = (pb - pa).squaredNorm();
    if (d < d2) {
      d2 = d;
      a = pa;
      b = pb;
    }
  }
};

Eigen::Vector3d closestOnRect(const Core& r, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - r.c;
  return r.c + std::clamp(d.dot(r.u), -r.hu, r.hu) * r.u +
         std::clamp(d.dot(r.v), -r.hv, r.hv) * r.v;
}

void segmentSegment(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                    const Eigen::Vector3d& q1, Candidate& out, bool swap) {
  double s = 0.0, t = 0.0;
  closestSegmentParameters(p0, p1, q0, q1, s, t);
  const Eigen::Vector3d a = p0 + s * (p1 - p0), b = q0 + t * (q1 - q0);
  if (swap)
    out.offer(b, a);
  else
    out.offer(a, b);
}

/// Segment [p0, p1] against rectangle r; the candidate's a lies on the segment (b on r), or the
/// other way round when swap is set.
void segmentRect(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Core& r,
                 Candidate& out, bool swap) {
  const auto offer = [&](const Eigen::Vector3d& on_seg, const Eigen::Vector3d& on_rect) {
    if (swap)
      out.offer(on_rect, on_seg);
    else
      out.offer(on_seg, on_rect);
  };
  const double h0 = (p0 - r.c).dot(r.n), h1 = (p1 - r.c).dot(r.n);
  if ((h0 <= 0.0 && h1 >= 0.0) || (h0 >= 0.0 && h1 <= 0.0)) {
    if (h0 != h1) {
      const Eigen::Vector3d x = p0 + (h0 / (h0 - h1)) * (p1 - p0);
      const Eigen::Vector3d d = x - r.c;
      if (std::abs(d.dot(r.u)) <= r.hu && std::abs(d.dot(r.v)) <= r.hv) {
        offer(x, x);
        return;
      }
    }
  }
  offer(p0, closestOnRect(r, p0));
  offer(p1, closestOnRect(r, p1));
  const std::array<Eigen::Vector3d, 4> corner = {
      r.c - r.hu * r.u - r.hv * r.v, r.c + r.hu * r.u - r.hv * r.v, r.c + r.hu * r.u + r.hv * r.v,
      r.c - r.hu * r.u + r.hv * r.v};
  const int edges = r.hv > 0.0 ? 4 : 1;  // a flat rectangle of width 0 is one segment
  for (int e = 0; e < edges; ++e) segmentSegment(p0, p1, corner[e], corner[(e + 1) % 4], out, swap);
}

void rectRect(const Core& a, const Core& b, Candidate& out) {
  const auto edgesOf = [](const Core& r, int e, Eigen::Vector3d& e0, Eigen::Vector3d& e1) {
    const double su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
    e0 = r.c + su[e] * r.hu * r.u + sv[e] * r.hv * r.v;
    e1 = r.c + su[(e + 1) % 4] * r.hu * r.u + sv[(e + 1) % 4] * r.hv * r.v;
  };
  Eigen::Vector3d e0, e1;
  for (int e = 0; e < 4; ++e) {
    edgesOf(a, e, e0, e1);
    segmentRect(e0, e1, b, out, false);
    if (out.d2 == 0.0) return;
    edgesOf(b, e, e0, e1);
    segmentRect(e0, e1, a, out, true);
    if (out.d2 == 0.0) return;
  }
}

}  // namespace

void closestSegmentParameters(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                              const Eigen::Vector3d& q0, const Eigen::Vector3d& q1, double& s,
                              double& t) {
  // Ericson, Real-Time Collision Detection, 5.1.9, with clamping of both parameters.
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  constexpr double kEps = 1e-24;
  if (a <= kEps && e <= kEps) {
    s = t = 0.0;
    return;
  }
  if (a <= kEps) {
    s = 0.0;
    t = std::clamp(f / e, 0.0, 1.0);
    return;
  }
  const double c = d1.dot(r);
  if (e <= kEps) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
    return;
  }
  const double b = d1.dot(d2), denom = a * e - b * b;
  s = denom > 1e-18 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
}

PrimitiveDistance primitiveDistance(const Primitive& a, const Eigen::Isometry3d& pose_a,
                                    const Primitive& b, const Eigen::Isometry3d& pose_b) {
  const Core ka = worldCore(a, pose_a), kb = worldCore(b, pose_b);
  Candidate best;
  if (!ka.rect && !kb.rect) {
    segmentSegment(ka.c - ka.hu * ka.u, ka.c + ka.hu * ka.u, kb.c - kb.hu * kb.u,
                   kb.c + kb.hu * kb.u, best, false);
  } else if (!ka.rect) {
    segmentRect(ka.c - ka.hu * ka.u, ka.c + ka.hu * ka.u, kb, best, false);
  } else if (!kb.rect) {
    segmentRect(kb.c - kb.hu * kb.u, kb.c + kb.hu * kb.u, ka, best, true);
  } else {
    rectRect(ka, kb, best);
  }
  PrimitiveDistance out;
  out.core_a = best.a;
  out.core_b = best.b;
  out.core_distance = std::sqrt(best.d2);
  if (out.core_distance > 1e-12) {
    out.normal = (best.b - best.a) / out.core_distance;
  } else {
    out.cores_touch = true;
    const Eigen::Vector3d dc = kb.c - ka.c;
    out.normal = dc.norm() > 1e-12 ? Eigen::Vector3d(dc.normalized()) : kb.n;
  }
  out.distance = out.core_distance - a.radius - b.radius;
  out.point_a = out.core_a + a.radius * out.normal;
  out.point_b = out.core_b - b.radius * out.normal;
  return out;
}

}  // namespace taskmap
