#include "taskmap/sampler/palm_enclose.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "taskmap/core/error.hpp"
#include "taskmap/sampler/sampler.hpp"

namespace taskmap {

namespace {

/// The probe depth is at least this far ahead of the palm's front, metres.
constexpr double kMinProbeDepth = 0.005;
/// The palm-face rays run this far in front of the surface point, metres (as antipodal_palm).
constexpr double kFaceClearance = 0.01;
/// Rays from a surface point start this far along so as not to hit their own triangle, metres.
constexpr double kRayStart = 1e-7;
/// Metres: no point of the open fingers may be nearer the surface than this (the simulator's
/// contact tolerance, GraspSimOptions::contact_tolerance): a finger point on the surface marks a
/// finger link that touches or cuts into the part between its check points, and the trial
/// retracts the hand off it and ends `no_palm_contact`.
constexpr double kFingerClearance = 5e-4;

Eigen::Vector3d centroid(const std::vector<Eigen::Vector3d>& pts) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : pts) c += p / static_cast<double>(pts.size());
  return c;
}

/// The closing axis: the principal direction, across a, of the fingers' centroid displacements
/// from the preshape to the closing targets (sum of d d^T, largest eigenvector). Zero when the
/// fingers do not move across a.
Eigen::Vector3d closingAxis(const std::vector<std::vector<Eigen::Vector3d>>& open,
                            const std::vector<std::vector<Eigen::Vector3d>>& closed,
                            const Eigen::Vector3d& a) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
  for (std::size_t f = 0; f < open.size(); ++f) {
    if (open[f].empty()) continue;
    Eigen::Vector3d d = centroid(closed[f]) - centroid(open[f]);
    d -= d.dot(a) * a;
    m += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(m);
  if (!(eig.eigenvalues()[2] > 1e-10)) return Eigen::Vector3d::Zero();
  Eigen::Vector3d c = eig.eigenvectors().col(2);
  c -= c.dot(a) * a;
  return c.normalized();
}

/// Metres: the smallest CollisionShape::thickness of the finger links' shapes (0 when none).
double thinnestFingerLink(const HandModel& hand) {
  double thin = std::numeric_limits<double>::infinity();
  for (const HandLink& link : hand.links())
    if (link.finger >= 0)
      for (const CollisionShape& shape : link.shapes) thin = std::min(thin, shape.thickness());
  return std::isfinite(thin) ? thin : 0.0;
}

}  // namespace

void EncloseGeometry::validate() const {
  if (!closing_axis.allFinite() || std::abs(closing_axis.norm() - 1.0) > 1e-6)
    throw Error("enclose closing_axis must be a finite unit vector");
  if (!std::isfinite(palm_front)) throw Error("enclose palm_front must be finite (metres)");
  if (!std::isfinite(probe_depth) || !(probe_depth > 0.0))
    throw Error("enclose probe_depth must be a positive length in metres");
  if (!std::isfinite(span_min) || !std::isfinite(span_max) || !(span_min < span_max))
    throw Error("enclose span_min must be below span_max (finite, metres)");
  if (!grasp_centre.allFinite()) throw Error("enclose grasp_centre must be finite (metres)");
  if (!palm_min.allFinite() || !palm_max.allFinite() || (palm_min.array() > palm_max.array()).any())
    throw Error("enclose palm_min and palm_max must be finite with palm_min <= palm_max (metres)");
  if (!std::isfinite(min_depth) || min_depth < 0.0)
    throw Error("enclose min_depth must be a finite length >= 0 in metres");
}

std::optional<EncloseGeometry> encloseGeometry(const HandModel& hand) {
  if (hand.fingerNames().size() < 2 || hand.closing().empty()) return std::nullopt;
  const Eigen::Vector3d a = hand.approachAxis().normalized();
  const Eigen::VectorXd open_q = hand.preshape();
  Eigen::VectorXd closed_q = open_q;
  for (const ClosingJoint& j : hand.closing()) closed_q[j.joint] = j.target;
  const auto open = fingerShapePoints(hand, open_q);
  const auto closed = fingerShapePoints(hand, closed_q);
  const Eigen::Vector3d c = closingAxis(open, closed, a);
  if (!(c.norm() > 0.5)) return std::nullopt;
  EncloseGeometry g;
  g.closing_axis = c;
  const Eigen::Vector3d v = c.cross(a);
  const std::vector<Eigen::Vector3d> palm = palmShapePoints(hand, open_q);
  if (!palm.empty()) {
    g.palm_front = -1e300;
    g.palm_min = g.palm_max = Eigen::Vector2d(c.dot(palm[0]), v.dot(palm[0]));
  }
  for (const Eigen::Vector3d& p : palm) {
    g.palm_front = std::max(g.palm_front, a.dot(p));
    g.palm_min = g.palm_min.cwiseMin(Eigen::Vector2d(c.dot(p), v.dot(p)));
    g.palm_max = g.palm_max.cwiseMax(Eigen::Vector2d(c.dot(p), v.dot(p)));
  }
  std::vector<Eigen::Vector3d> all_open, all_closed;
  for (const auto& f : open) all_open.insert(all_open.end(), f.begin(), f.end());
  for (const auto& f : closed) all_closed.insert(all_closed.end(), f.begin(), f.end());
  if (all_open.empty()) return std::nullopt;
  g.span_min = 1e300;
  g.span_max = -1e300;
  for (const Eigen::Vector3d& p : all_open) {
    g.span_min = std::min(g.span_min, c.dot(p));
    g.span_max = std::max(g.span_max, c.dot(p));
  }
  const Eigen::Vector3d shut = centroid(all_closed);
  g.probe_depth = std::max(kMinProbeDepth, a.dot(shut) - g.palm_front);
  g.grasp_centre = Eigen::Vector2d(c.dot(shut), 0.5 * (g.palm_min.y() + g.palm_max.y()));
  g.min_depth = 0.5 * thinnestFingerLink(hand);
  return g;
}

namespace {

/// Surface crossings met from x along d are walked at most this many times per side.
constexpr int kMaxCrossings = 16;
/// A walk restarts this far past each crossing, metres.
constexpr double kStep = 1e-7;

/// How far the object reaches from x along d (unit) within max_len, metres: the distance of the
/// last surface crossing of the ray x + s d for s in (0, max_len], 0 when it crosses nothing
/// and x is outside (`inside`: whether x is in the solid); empty when the ray is still inside
/// the solid at max_len (the object reaches past it) or crosses more than kMaxCrossings times.
/// Walks through hollows: a mug's wall, the hollow and the far wall give the mug's outer
/// extent, not the wall's. `first`, when given, is the ray's first hit already cast
/// (castRay(x, d, 0, max_len)): the walk starts from it with the same result.
std::optional<double> reach(const ObjectModel& object, const Eigen::Vector3d& x,
                            const Eigen::Vector3d& d, double max_len, bool inside,
                            const RayHit* first = nullptr) {
  double at = 0.0, last = 0.0;
  for (int k = 0; k <= kMaxCrossings; ++k) {
    if (!(max_len - at > kStep)) break;
    const std::optional<RayHit> hit = k == 0 && first != nullptr
                                          ? std::optional<RayHit>(*first)
                                          : object.castRay(x + at * d, d, 0.0, max_len - at);
    if (!hit) break;
    if (k == kMaxCrossings) return std::nullopt;
    last = at + hit->distance;
    inside = hit->normal.dot(d) < 0.0;  // an entry: the solid continues past it
    at = last + kStep;
  }
  if (inside) return std::nullopt;
  return last;
}

/// The object's extent through x along d: how far it reaches along +d and along -d (reach),
/// empty unless both sides together fit within max_len (the ray along -d only searches the
/// length the ray along +d left: a part wider than the span costs one side's rays, not two) or
/// when the line meets nothing. `first`, when given, holds the first hits of the rays along +d
/// within max_len and along -d within max_len less the +d hit's distance (firstChord's): the
/// walks start from them where their range is the same, with the same result.
std::optional<std::pair<double, double>> chord(const ObjectModel& object, const Eigen::Vector3d& x,
                                               const Eigen::Vector3d& d, double max_len,
                                               bool inside,
                                               const std::pair<RayHit, RayHit>* first = nullptr) {
  const std::optional<double> plus =
      reach(object, x, d, max_len, inside, first != nullptr ? &first->first : nullptr);
  if (!plus) return std::nullopt;
  const double rest = max_len - *plus;
  if (!(rest > 0.0)) return std::nullopt;
  // The -d ray's first hit within the shorter range is the one cast when it lies within it.
  const bool seed = first != nullptr && first->second.distance <= rest;
  const std::optional<double> minus =
      reach(object, x, -d, rest, inside, seed ? &first->second : nullptr);
  if (!minus || !(*plus + *minus > 0.0)) return std::nullopt;
  return std::make_pair(*plus, *minus);
}

/// A crossing more than this past a first hit may be one a walk restarting kStep past it finds
/// (half of kStep: rounding of the restarted ray's distances cannot hide one), metres.
constexpr double kAgainGap = 0.5 * kStep;

/// The first crossings of the rays x + s d and x - s d (firstChord) and whether each ray crosses
/// the surface again past its hit within the range chord() would walk it (castRayAndAgain, gap
/// kAgainGap).
struct FirstChord {
  RayHit plus, minus;
  bool again_plus = true, again_minus = true;
};

/// The chord of the solid through x (inside it) along d: distances to where the rays x + s d
/// and x - s d first leave it, empty unless both fit within max_len together. A lower bound of
/// chord()'s extent, two rays; the hits themselves (chord() walks on from them).
std::optional<FirstChord> firstChord(const ObjectModel& object, const Eigen::Vector3d& x,
                                     const Eigen::Vector3d& d, double max_len) {
  FirstChord c;
  const std::optional<RayHit> plus =
      object.castRayAndAgain(x, d, 0.0, max_len, kAgainGap, &c.again_plus);
  if (!plus) return std::nullopt;
  const double rest = max_len - plus->distance;
  if (!(rest > 0.0)) return std::nullopt;
  const std::optional<RayHit> minus =
      object.castRayAndAgain(x, -d, 0.0, rest, kAgainGap, &c.again_minus);
  if (!minus) return std::nullopt;
  c.plus = *plus;
  c.minus = *minus;
  return c;
}

/// chord(object, x, d, max_len, true, first)'s answer: each side walks on from its first hit,
/// and where the ray does not cross again within the walk's range (max_len for +d, what +d left
/// for -d: firstChord's ranges) the walk ends there, an exit, without casting again.
std::optional<std::pair<double, double>> walkedChord(const ObjectModel& object,
                                                     const Eigen::Vector3d& x,
                                                     const Eigen::Vector3d& d, double max_len,
                                                     const FirstChord& f) {
  if (f.again_plus || f.again_minus) {
    const std::pair<RayHit, RayHit> first{f.plus, f.minus};
    return chord(object, x, d, max_len, true, &first);
  }
  // reach(): after a lone hit the ray is inside when it entered there.
  if (f.plus.normal.dot(d) < 0.0 || f.minus.normal.dot(-d) < 0.0) return std::nullopt;
  if (!(f.plus.distance + f.minus.distance > 0.0)) return std::nullopt;
  return std::make_pair(f.plus.distance, f.minus.distance);
}

/// The object's depth along w (unit) from the surface point q (on the surface, w into the
/// solid): where the solid first ends; when that is within twice `probe_depth`, its last
/// crossing (through a hollow to the far wall). Empty when the ray from q leaves nothing (q is
/// not in front of the solid) or the walk through the hollow does not end.
std::optional<std::pair<double, RayHit>> throughDepth(const ObjectModel& object,
                                                      const Eigen::Vector3d& q,
                                                      const Eigen::Vector3d& w,
                                                      double probe_depth) {
  const std::optional<RayHit> exit = object.castRay(q, w, kRayStart);
  if (!exit) return std::nullopt;
  double through = exit->distance;
  if (through < 2.0 * probe_depth) {
    const std::optional<double> rest =
        reach(object, exit->point + kStep * w, w, std::numeric_limits<double>::infinity(), false);
    if (!rest) return std::nullopt;
    if (*rest > 0.0) through += kStep + *rest;
  }
  return std::make_pair(through, *exit);
}

/// Whether the object reaches at least g.min_depth ahead of the palm's front at the chord's
/// midpoint `mid` (at depth `depth` behind the face plane through q): the first surface met
/// along w from kFaceClearance in front of that plane (within min_depth behind it), then
/// throughDepth from there; the far end must lie min_depth or more behind the plane. With
/// `through` (the depth at q) at least min_depth, no ray is cast.
bool deepEnough(const ObjectModel& object, const EncloseGeometry& g, const Eigen::Vector3d& mid,
                const Eigen::Vector3d& w, double depth, double through) {
  if (through >= g.min_depth) return true;
  const Eigen::Vector3d start = mid - (depth + kFaceClearance) * w;
  const std::optional<RayHit> entry = object.castRay(start, w, 0.0, kFaceClearance + g.min_depth);
  if (!entry) return false;
  const auto at_mid = throughDepth(object, entry->point, w, g.probe_depth);
  return at_mid && entry->distance - kFaceClearance + at_mid->first >= g.min_depth;
}

/// Rays in the plane kFaceClearance in front of q (outside the surface) from `face` along +-c
/// and +-v to the palm's extent and to its four corners: none may meet the surface (the palm
/// would cut through the part). face_cv: the face point's palm-frame (c, v) coordinates, metres.
bool faceClear(const ObjectModel& object, const EncloseGeometry& g, const Eigen::Vector3d& face,
               const Eigen::Vector2d& face_cv, const Eigen::Vector3d& cw,
               const Eigen::Vector3d& vw) {
  const Eigen::Vector3d axes[2] = {cw, vw};
  for (int k = 0; k < 2; ++k) {
    const double reach[2] = {g.palm_max[k] - face_cv[k], face_cv[k] - g.palm_min[k]};
    for (int side = 0; side < 2; ++side) {
      if (!(reach[side] > 0.0)) continue;
      const Eigen::Vector3d d = side == 0 ? axes[k] : Eigen::Vector3d(-axes[k]);
      if (object.castRay(face, d, 0.0, reach[side])) return false;
    }
  }
  // And to the palm's four corners (a handle beside the face, off the axes).
  for (int sc = 0; sc < 2; ++sc)
    for (int sv = 0; sv < 2; ++sv) {
      const Eigen::Vector3d to = ((sc == 0 ? g.palm_max.x() : g.palm_min.x()) - face_cv.x()) * cw +
                                 ((sv == 0 ? g.palm_max.y() : g.palm_min.y()) - face_cv.y()) * vw;
      const double len = to.norm();
      if (len > 0.0 && object.castRay(face, to / len, 0.0, len)) return false;
    }
  return true;
}

/// fingersOutside's memory within one draw: the last failing points and scratch buffers.
struct FingerHint {
  std::size_t inside = 0;  ///< the point last found inside
  std::size_t near = 0;    ///< the point last found within kFingerClearance of the surface
  std::vector<std::size_t> candidates;  ///< scratch: points within the object's grown bounds
  std::vector<Eigen::Vector3d> world;   ///< scratch: their positions in the object frame
};

/// No point of the open fingers is inside the object, nor within kFingerClearance of its
/// surface (the inside tests first: a pose with a finger over a face fails after a few).
/// `hint`: the indices of the points found inside and near the surface by the previous calls of
/// one draw, tested first (the same fingertip usually cuts the part at the next roll and point:
/// one test instead of dozens); updated on each such failure. Points outside the object's
/// bounds grown by kFingerClearance are neither (no query). The answer does not depend on the
/// hints or the bounds test.
bool fingersOutside(const ObjectModel& object, const Pose& palm,
                    const std::vector<Eigen::Vector3d>& points, FingerHint* hint) {
  const Eigen::Matrix3d r = palm.orientation.toRotationMatrix();
  const MassProperties& mp = object.massProperties();
  const Eigen::Vector3d lo = mp.bounds_min.array() - kFingerClearance;
  const Eigen::Vector3d hi = mp.bounds_max.array() + kFingerClearance;
  const auto inBounds = [&lo, &hi](const Eigen::Vector3d& x) {
    return (x.array() >= lo.array()).all() && (x.array() <= hi.array()).all();
  };
  const auto world = [&](std::size_t i) { return Eigen::Vector3d(palm.position + r * points[i]); };
  if (hint->inside < points.size()) {
    const Eigen::Vector3d x = world(hint->inside);
    if (inBounds(x) && object.contains(x)) return false;
  }
  // The points within the grown bounds, in order, with their world positions (the rest cannot
  // fail either test).
  hint->candidates.clear();
  hint->world.clear();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d x = world(i);
    if (!inBounds(x)) continue;
    hint->candidates.push_back(i);
    hint->world.push_back(x);
  }
  const std::size_t n = hint->candidates.size();
  for (std::size_t k = 0; k < n; ++k)
    if (hint->candidates[k] != hint->inside && object.contains(hint->world[k])) {
      hint->inside = hint->candidates[k];
      return false;
    }
  if (hint->near < points.size()) {
    const Eigen::Vector3d x = world(hint->near);
    if (inBounds(x) && object.nearSurface(x, kFingerClearance)) return false;
  }
  for (std::size_t k = 0; k < n; ++k)
    if (hint->candidates[k] != hint->near && object.nearSurface(hint->world[k], kFingerClearance)) {
      hint->near = hint->candidates[k];
      return false;
    }
  return true;
}

struct Candidate {
  double width = 0.0, plus = 0.0, minus = 0.0;
  Eigen::Vector3d dir = Eigen::Vector3d::Zero();
  std::optional<FirstChord> first;  ///< firstChord's hits (x inside the solid)
};

/// One surface point: the kEncloseRolls directions across w = -n, narrowest chord first, each
/// placed and checked; the first accepted pose. `finger_hint`: fingersOutside's.
std::optional<Pose> tryPoint(const ObjectModel& object, const EncloseGeometry& g,
                             const Eigen::Vector3d& a,
                             const std::vector<Eigen::Vector3d>& finger_points,
                             const SurfaceSample& q, double roll, double margin,
                             FingerHint* finger_hint) {
  const Eigen::Vector3d w = -q.normal;
  const auto at_q = throughDepth(object, q.point, w, g.probe_depth);
  if (!at_q) return std::nullopt;
  const double through = at_q->first;
  const RayHit* const exit = &at_q->second;
  const double depth = std::min(g.probe_depth, 0.5 * through);
  const Eigen::Vector3d x = q.point + depth * w;
  // x is in the solid unless the first exit is shallower than the probe (a hollow's wall).
  const bool inside = depth < exit->distance || object.contains(x);
  const double span = g.span_max - g.span_min - 2.0 * margin;
  const Eigen::Vector3d e1 = w.unitOrthogonal(), e2 = w.cross(e1);
  std::array<Candidate, kEncloseRolls> cands;
  for (int k = 0; k < kEncloseRolls; ++k) {
    const double t = roll + M_PI * k / kEncloseRolls;
    cands[k].dir = std::cos(t) * e1 + std::sin(t) * e2;
    std::optional<std::pair<double, double>> ch;
    if (inside) {
      cands[k].first = firstChord(object, x, cands[k].dir, span);
      if (cands[k].first)
        ch = std::make_pair(cands[k].first->plus.distance, cands[k].first->minus.distance);
    } else {
      ch = chord(object, x, cands[k].dir, span, inside);
    }
    cands[k].width = ch ? ch->first + ch->second : 1e300;
    if (ch) cands[k].plus = ch->first, cands[k].minus = ch->second;
  }
  std::array<int, kEncloseRolls> order;
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&cands](int i, int j) { return cands[i].width < cands[j].width; });
  const Eigen::Vector3d cp = g.closing_axis;
  Eigen::Matrix3d palm;
  palm << cp, a, cp.cross(a);
  for (int k : order) {
    Candidate& cd = cands[k];
    if (!(cd.width <= span)) break;
    // A part lower than min_depth ahead of the palm where the fingers close (at the midpoint
    // of the chord's first crossings): the fingers would fold over it onto the palm.
    if (!deepEnough(object, g, x + 0.5 * (cd.plus - cd.minus) * cd.dir, w, depth, through))
      continue;
    if (inside) {
      // The first crossings bound the extent from below; the whole extent (a part that
      // continues past a gap) must fit too.
      const auto ch = walkedChord(object, x, cd.dir, span, *cd.first);
      if (!ch) continue;
      cd.plus = ch->first, cd.minus = ch->second, cd.width = ch->first + ch->second;
    }
    // The chord [x - minus d, x + plus d] in palm c-coordinates, centred on the grasp centre,
    // shifted to lie within the span (with margin).
    double centre = g.grasp_centre.x();
    centre = std::clamp(centre, g.span_min + margin + 0.5 * cd.width,
                        g.span_max - margin - 0.5 * cd.width);
    const Eigen::Vector3d mid = x + 0.5 * (cd.plus - cd.minus) * cd.dir;
    Eigen::Matrix3d world;
    world << cd.dir, w, cd.dir.cross(w);
    const Eigen::Matrix3d r = world * palm.transpose();
    const Eigen::Vector3d vw = cd.dir.cross(w);
    Pose pose;
    pose.orientation = Eigen::Quaterniond(r).normalized();
    pose.position = (w.dot(q.point) - g.palm_front) * w + (cd.dir.dot(mid) - centre) * cd.dir +
                    (vw.dot(q.point) - g.grasp_centre.y()) * vw;
    // q's palm-frame coordinates: along c the chord's centre less its offset from x, along v
    // the grasp centre's.
    const Eigen::Vector2d face_cv(centre - 0.5 * (cd.plus - cd.minus), g.grasp_centre.y());
    // Both checks must pass; the finger points first (they reject most candidates, the face's
    // eight rays few).
    if (!fingersOutside(object, pose, finger_points, finger_hint)) continue;
    if (!faceClear(object, g, q.point - kFaceClearance * w, face_cv, cd.dir, vw)) continue;
    return pose;
  }
  return std::nullopt;
}

}  // namespace

std::vector<Eigen::Vector3d> coarseToFine(const std::vector<Eigen::Vector3d>& points) {
  // Key of index i: its count of trailing zero bits (index 0 first of all).
  const auto key = [](std::size_t i) {
    if (i == 0) return 64;
    int z = 0;
    while ((i & 1u) == 0) i >>= 1, ++z;
    return z;
  };
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&key](std::size_t x, std::size_t y) { return key(x) > key(y); });
  std::vector<Eigen::Vector3d> out;
  out.reserve(points.size());
  for (std::size_t i : order) out.push_back(points[i]);
  return out;
}

std::optional<Pose> drawPalmEnclose(const ObjectModel& object, const EncloseGeometry& geometry,
                                    const Eigen::Vector3d& approach_axis,
                                    const std::vector<Eigen::Vector3d>& finger_points, int attempts,
                                    double margin, Rng& rng) {
  FingerHint finger_hint;
  for (int k = 0; k < attempts; ++k) {
    const SurfaceSample q = object.sampleSurface(rng);
    const double roll = rng.uniform(0.0, 2.0 * M_PI);
    std::optional<Pose> pose =
        tryPoint(object, geometry, approach_axis, finger_points, q, roll, margin, &finger_hint);
    if (pose) return pose;
  }
  return std::nullopt;
}

}  // namespace taskmap
