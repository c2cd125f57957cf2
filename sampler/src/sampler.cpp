#include "taskmap/sampler/sampler.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include <Eigen/Geometry>

#include "taskmap/core/error.hpp"
#include "taskmap/core/random.hpp"

namespace taskmap {

const char* toString(SamplerKind kind) {
  switch (kind) {
    case SamplerKind::kVolume:
      return "volume";
    case SamplerKind::kSurface:
      return "surface";
    case SamplerKind::kMixed:
      return "mixed";
    case SamplerKind::kAntipodal:
      return "antipodal";
    case SamplerKind::kEnclose:
      return "enclose";
    case SamplerKind::kAntipodalPalm:
      return "antipodal_palm";
    case SamplerKind::kPalmEnclose:
      return "palm_enclose";
  }
  return "mixed";
}

SamplerKind samplerKindFromString(const std::string& name) {
  if (name == "volume") return SamplerKind::kVolume;
  if (name == "surface") return SamplerKind::kSurface;
  if (name == "mixed") return SamplerKind::kMixed;
  if (name == "antipodal") return SamplerKind::kAntipodal;
  if (name == "enclose") return SamplerKind::kEnclose;
  if (name == "antipodal_palm") return SamplerKind::kAntipodalPalm;
  if (name == "palm_enclose") return SamplerKind::kPalmEnclose;
  throw Error("unknown sampler '" + name +
              "': use volume, surface, mixed, antipodal, enclose, antipodal_palm or palm_enclose");
}

void JawGeometry::validate() const {
  if (!closing_axis.allFinite() || std::abs(closing_axis.norm() - 1.0) > 1e-6)
    throw Error("jaw closing_axis must be a finite unit vector");
  if (!pad_midpoint.allFinite()) throw Error("jaw pad_midpoint must be finite (metres)");
  if (!std::isfinite(open_width) || !(open_width > 0.0))
    throw Error("jaw open_width must be a positive length in metres");
  if (!std::isfinite(closed_width) || closed_width >= open_width)
    throw Error("jaw closed_width must be finite and below open_width (metres)");
  if (!std::isfinite(palm_front)) throw Error("jaw palm_front must be finite (metres)");
  if (!palm_min.allFinite() || !palm_max.allFinite() || (palm_min.array() > palm_max.array()).any())
    throw Error("jaw palm_min and palm_max must be finite with palm_min <= palm_max (metres)");
}

void SamplerOptions::validate() const {
  if (!approach_axis.allFinite() || std::abs(approach_axis.norm() - 1.0) > 1e-6)
    throw Error("sampler approach_axis must be a finite unit vector");
  if (!std::isfinite(standoff_min) || !std::isfinite(standoff_max))
    throw Error("sampler standoff_min and standoff_max must be finite (metres)");
  if (standoff_min > standoff_max) throw Error("sampler standoff_min must not exceed standoff_max");
  if (!std::isfinite(friction) || friction < 0.0)
    throw Error("sampler friction must be a finite coefficient >= 0");
  if (attempts < 1) throw Error("sampler attempts must be at least 1");
  if (!std::isfinite(width_margin) || width_margin < 0.0)
    throw Error("sampler width_margin must be a finite length >= 0 in metres");
  if (!std::isfinite(enclose_margin) || enclose_margin < 0.0)
    throw Error("sampler enclose_margin must be a finite length >= 0 in metres");
  if (jaws) jaws->validate();
  if (enclose) enclose->validate();
  for (const Eigen::Vector3d& p : finger_points)
    if (!p.allFinite()) throw Error("sampler finger_points must be finite (metres)");
}

namespace {

/// Points spanning a collision shape, in its link frame: box corners, hull points, the
/// extreme points of spheres and cylinders along the shape's axes.
void shapePoints(const CollisionShape& s, std::vector<Eigen::Vector3d>* out) {
  std::vector<Eigen::Vector3d> local;
  switch (s.type) {
    case ShapeType::kBox:
      for (int i = 0; i < 8; ++i)
        local.push_back(0.5 * Eigen::Vector3d((i & 1) ? s.box_size.x() : -s.box_size.x(),
                                              (i & 2) ? s.box_size.y() : -s.box_size.y(),
                                              (i & 4) ? s.box_size.z() : -s.box_size.z()));
      break;
    case ShapeType::kSphere:
      for (int k = 0; k < 3; ++k)
        for (double sign : {-1.0, 1.0}) local.push_back(sign * s.radius * Eigen::Vector3d::Unit(k));
      break;
    case ShapeType::kCylinder:
      for (int k = 0; k < 8; ++k) {
        const double phi = 2.0 * M_PI * k / 8.0;
        for (double sign : {-1.0, 1.0})
          local.emplace_back(s.radius * std::cos(phi), s.radius * std::sin(phi),
                             0.5 * sign * s.length);
      }
      break;
    case ShapeType::kConvex:
      local = s.points;
      break;
  }
  for (const Eigen::Vector3d& p : local) out->push_back(s.origin * p);
}

/// Moving joints (not fixed) between link `l` and the root.
int movingDepth(const HandModel& hand, int l) {
  int depth = 0;
  while (l >= 0) {
    const int j = hand.links()[static_cast<std::size_t>(l)].parent_joint;
    if (j < 0) break;
    const HandJoint& joint = hand.joints()[static_cast<std::size_t>(j)];
    if (joint.type != JointType::kFixed) ++depth;
    l = joint.parent_link;
  }
  return depth;
}

/// Per link: true when it has shapes, belongs to a finger, and no link with shapes of the same
/// finger lies behind more moving joints (the finger's distal body: a Robotiq's inner finger
/// and pad, not its knuckles; the whole finger of a one-link jaw).
std::vector<char> distalLinks(const HandModel& hand) {
  const std::size_t n = hand.links().size();
  std::vector<int> depth(n, -1), deepest(hand.fingerNames().size(), -1);
  for (std::size_t l = 0; l < n; ++l) {
    const HandLink& link = hand.links()[l];
    if (link.finger < 0 || link.shapes.empty()) continue;
    depth[l] = movingDepth(hand, static_cast<int>(l));
    int& d = deepest[static_cast<std::size_t>(link.finger)];
    d = std::max(d, depth[l]);
  }
  std::vector<char> out(n, 0);
  for (std::size_t l = 0; l < n; ++l)
    if (depth[l] >= 0)
      out[l] = depth[l] == deepest[static_cast<std::size_t>(hand.links()[l].finger)];
  return out;
}

/// Every point of every shape of each finger (only its distal body when `distal_only`), palm
/// frame, at joint values q.
std::vector<std::vector<Eigen::Vector3d>> fingerPoints(const HandModel& hand,
                                                       const Eigen::VectorXd& q,
                                                       bool distal_only = false) {
  std::vector<std::vector<Eigen::Vector3d>> fingers(hand.fingerNames().size());
  const std::vector<Eigen::Isometry3d> poses = hand.linkPoses(q);
  const std::vector<char> distal = distal_only ? distalLinks(hand) : std::vector<char>();
  for (std::size_t l = 0; l < hand.links().size(); ++l) {
    const HandLink& link = hand.links()[l];
    if (link.finger < 0 || (distal_only && !distal[l])) continue;
    std::vector<Eigen::Vector3d> pts;
    for (const CollisionShape& s : link.shapes) shapePoints(s, &pts);
    for (const Eigen::Vector3d& p : pts)
      fingers[static_cast<std::size_t>(link.finger)].push_back(poses[l] * p);
  }
  return fingers;
}

Eigen::Vector3d centroid(const std::vector<Eigen::Vector3d>& pts) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : pts) c += p / static_cast<double>(pts.size());
  return c;
}

/// Inner faces of the two fingers along `axis`: the largest coordinate of the first finger and
/// the smallest of the second.
std::pair<double, double> innerFaces(const std::vector<std::vector<Eigen::Vector3d>>& f,
                                     const Eigen::Vector3d& axis) {
  double a = -1e300, b = 1e300;
  for (const Eigen::Vector3d& p : f[0]) a = std::max(a, axis.dot(p));
  for (const Eigen::Vector3d& p : f[1]) b = std::min(b, axis.dot(p));
  return {a, b};
}

/// Centroid of a finger's points within `band` of its inner face `face` along `axis`.
Eigen::Vector3d padCentre(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& axis,
                          double face, double band) {
  std::vector<Eigen::Vector3d> pad;
  for (const Eigen::Vector3d& p : pts)
    if (std::abs(axis.dot(p) - face) <= band) pad.push_back(p);
  return centroid(pad);
}

constexpr double kPadBand = 0.002;  ///< metres: a pad is the finger's points this near its face
/// antipodal_palm: spins tried per pair, evenly spaced from the drawn one.
constexpr int kSpins = 4;
/// Rays from a surface point start this far along so as not to hit their own triangle, metres.
constexpr double kRayStart = 1e-7;
/// antipodal_palm: the palm-face rays run this far in front of the surface point, metres.
constexpr double kPalmClearance = 0.01;
/// antipodal_palm: no point of the open fingers may come nearer the surface than this, metres
/// (twice the simulator's default contact tolerance: a finger that grazes the object touches
/// before the palm, and the trial ends no_palm_contact; a panda on a sphere as wide as its
/// opening did so in every trial).
constexpr double kJawFingerClearance = 1e-3;
/// antipodal_palm: the clearance is tested on one finger point per cube of this edge, metres.
constexpr double kClearanceCell = 0.004;
/// The finger points are grouped by cube of this edge, metres; a group of at least
/// kGroupTestMin points is first tested as a ball (Sampler::FingerGroup).
constexpr double kGroupCell = 0.01;
constexpr std::size_t kGroupTestMin = 8;
/// antipodal_palm and palm_enclose: attempts of the construction-time probe, and its generator's
/// seed (trial k of the probe draws from Rng(kProbeSeed, k)).
constexpr int kProbeAttempts = 64;
constexpr std::uint64_t kProbeSeed = 0x70726f6265ULL;  // "probe"
/// antipodal_palm and palm_enclose: below this share of trials finding a pose within
/// `attempts`, they make no attempt: their trials are the mixed sampler's
/// (Sampler::attemptsInForce). 0.25 with 16 attempts: a probe accepting 2 of 64 attempts
/// (the panda's jaws on the reference mug) attempts; 1 of 64 does not
/// (docs/history/performance-2026-11.md, "The probe's threshold"; 0.5 before 2026-11-27).
constexpr double kProbeMinFound = 0.25;

/// antipodal_palm: how far the pads' midpoint lies ahead of the palm's front along the approach
/// axis `a`, metres (positive for a usable jaw).
double palmDepth(const JawGeometry& jaws, const Eigen::Vector3d& a) {
  return a.dot(jaws.pad_midpoint) - jaws.palm_front;
}

/// The palm-rigid links' shape points at q, palm frame.
std::vector<Eigen::Vector3d> palmPoints(const HandModel& hand, const Eigen::VectorXd& q) {
  const std::vector<Eigen::Isometry3d> poses = hand.linkPoses(q);
  std::vector<Eigen::Vector3d> out;
  for (std::size_t l = 0; l < hand.links().size(); ++l) {
    const HandLink& link = hand.links()[l];
    if (!link.palm) continue;
    std::vector<Eigen::Vector3d> pts;
    for (const CollisionShape& s : link.shapes) shapePoints(s, &pts);
    for (const Eigen::Vector3d& p : pts) out.push_back(poses[l] * p);
  }
  return out;
}

/// The palm's front along a and its extent across (along c and c x a), from its points.
void palmExtent(const std::vector<Eigen::Vector3d>& palm, const Eigen::Vector3d& a,
                JawGeometry* g) {
  if (palm.empty()) return;
  const Eigen::Vector3d c = g->closing_axis, v = c.cross(a);
  g->palm_front = -1e300;
  g->palm_min.setConstant(1e300);
  g->palm_max.setConstant(-1e300);
  for (const Eigen::Vector3d& p : palm) {
    g->palm_front = std::max(g->palm_front, a.dot(p));
    const Eigen::Vector2d x(c.dot(p), v.dot(p));
    g->palm_min = g->palm_min.cwiseMin(x);
    g->palm_max = g->palm_max.cwiseMax(x);
  }
}

/// Extra points of a shape for inside tests, shape's link frame: a grid at most `spacing` apart
/// on each box face, rings on a cylinder's side, midpoints of hull points closer than 2 spacing.
void densePoints(const CollisionShape& s, double spacing, std::vector<Eigen::Vector3d>* out) {
  std::vector<Eigen::Vector3d> local;
  if (s.type == ShapeType::kBox) {
    const Eigen::Vector3d h = 0.5 * s.box_size;
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      const int ni = std::max(1, static_cast<int>(std::ceil(s.box_size[i] / spacing)));
      const int nj = std::max(1, static_cast<int>(std::ceil(s.box_size[j] / spacing)));
      for (double sign : {-1.0, 1.0})
        for (int a = 0; a <= ni; ++a)
          for (int b = 0; b <= nj; ++b) {
            Eigen::Vector3d p;
            p[k] = sign * h[k];
            p[i] = -h[i] + s.box_size[i] * a / ni;
            p[j] = -h[j] + s.box_size[j] * b / nj;
            local.push_back(p);
          }
    }
  } else if (s.type == ShapeType::kCylinder) {
    const int rings = std::max(1, static_cast<int>(std::ceil(s.length / spacing)));
    for (int r = 0; r <= rings; ++r)
      for (int k = 0; k < 8; ++k) {
        const double phi = 2.0 * M_PI * k / 8.0;
        local.emplace_back(s.radius * std::cos(phi), s.radius * std::sin(phi),
                           -0.5 * s.length + s.length * r / rings);
      }
  } else if (s.type == ShapeType::kConvex) {
    for (std::size_t i = 0; i < s.points.size(); ++i)
      for (std::size_t j = i + 1; j < s.points.size(); ++j)
        if ((s.points[i] - s.points[j]).norm() < 2.0 * spacing)
          local.push_back(0.5 * (s.points[i] + s.points[j]));
  }
  for (const Eigen::Vector3d& p : local) out->push_back(s.origin * p);
}

}  // namespace

std::optional<JawGeometry> jawGeometry(const HandModel& hand) {
  if (hand.fingerNames().size() != 2 || hand.closing().empty()) return std::nullopt;
  const Eigen::VectorXd open = hand.preshape();
  // The pads are on each finger's distal body: a knuckle nearer the palm (a Robotiq's inner
  // knuckles, 13 mm apart) is not what closes on the object.
  const auto fingers = fingerPoints(hand, open, true);
  if (fingers[0].empty() || fingers[1].empty()) return std::nullopt;
  const Eigen::Vector3d a = hand.approachAxis().normalized();
  Eigen::Vector3d c = centroid(fingers[1]) - centroid(fingers[0]);
  c -= c.dot(a) * a;
  if (!(c.norm() > 1e-6)) return std::nullopt;
  c.normalize();
  const auto [face0, face1] = innerFaces(fingers, c);
  Eigen::VectorXd closed = open;
  for (const ClosingJoint& j : hand.closing()) closed[j.joint] = j.target;
  const auto [closed0, closed1] = innerFaces(fingerPoints(hand, closed, true), c);
  JawGeometry g;
  g.closing_axis = c;
  g.open_width = face1 - face0;
  g.closed_width = closed1 - closed0;
  if (!(g.open_width > 0.0) || !(g.closed_width < g.open_width)) return std::nullopt;
  const Eigen::Vector3d pad0 = padCentre(fingers[0], c, face0, kPadBand);
  const Eigen::Vector3d pad1 = padCentre(fingers[1], c, face1, kPadBand);
  g.pad_midpoint = 0.5 * (pad0 + pad1);
  // On the axis: halfway between the faces; across it: the pads' mean.
  g.pad_midpoint += (0.5 * (face0 + face1) - c.dot(g.pad_midpoint)) * c;
  palmExtent(palmPoints(hand, open), a, &g);
  return g;
}

std::vector<Eigen::Vector3d> openFingerPoints(const HandModel& hand) {
  std::vector<Eigen::Vector3d> out;
  for (const std::vector<Eigen::Vector3d>& f : fingerPoints(hand, hand.preshape()))
    out.insert(out.end(), f.begin(), f.end());
  return out;
}

std::vector<Eigen::Vector3d> fingerCheckPoints(const HandModel& hand, double spacing) {
  if (!std::isfinite(spacing) || !(spacing > 0.0))
    throw Error("fingerCheckPoints needs a positive spacing in metres");
  std::vector<Eigen::Vector3d> out = openFingerPoints(hand);
  const std::vector<Eigen::Isometry3d> poses = hand.linkPoses(hand.preshape());
  for (std::size_t l = 0; l < hand.links().size(); ++l) {
    const HandLink& link = hand.links()[l];
    if (link.finger < 0) continue;
    std::vector<Eigen::Vector3d> pts;
    for (const CollisionShape& s : link.shapes) densePoints(s, spacing, &pts);
    for (const Eigen::Vector3d& p : pts) out.push_back(poses[l] * p);
  }
  // Farthest from the palm first: fingertips enter the object first, so a rejected pose is
  // usually rejected by its first points.
  const Eigen::Vector3d a = hand.approachAxis().normalized();
  std::stable_sort(
      out.begin(), out.end(),
      [&a](const Eigen::Vector3d& x, const Eigen::Vector3d& y) { return a.dot(x) > a.dot(y); });
  return out;
}

std::vector<std::vector<Eigen::Vector3d>> fingerShapePoints(const HandModel& hand,
                                                            const Eigen::VectorXd& q) {
  return fingerPoints(hand, q);
}

std::vector<Eigen::Vector3d> palmShapePoints(const HandModel& hand, const Eigen::VectorXd& q) {
  return palmPoints(hand, q);
}

std::optional<AntipodalPair> antipodalAttempt(const ObjectModel& object, Rng& rng, double friction,
                                              double min_width, double max_width) {
  const SurfaceSample s = object.sampleSurface(rng);
  // Direction uniform in solid angle in the cone of half-angle atan(mu) about -n1.
  const double cos_cone = 1.0 / std::sqrt(1.0 + friction * friction);
  const double cos_t = rng.uniform(cos_cone, 1.0);
  const double phi = rng.uniform(0.0, 2.0 * M_PI);
  const Eigen::Vector3d inward = -s.normal;
  const Eigen::Vector3d e1 = inward.unitOrthogonal(), e2 = inward.cross(e1);
  const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
  const Eigen::Vector3d d =
      (cos_t * inward + sin_t * (std::cos(phi) * e1 + std::sin(phi) * e2)).normalized();
  // Start a hair inside so that the ray does not hit its own triangle.
  const double start = 1e-7;
  const std::optional<RayHit> hit = object.castRay(s.point, d, start, max_width + start);
  if (!hit) return std::nullopt;
  AntipodalPair p{s.point, s.normal, hit->point, hit->normal};
  const Eigen::Vector3d axis = p.p2 - p.p1;
  const double w = axis.norm();
  if (w < min_width || w > max_width || !(w > 0.0)) return std::nullopt;
  const Eigen::Vector3d u = axis / w;
  if (-p.n1.dot(u) < cos_cone || p.n2.dot(u) < cos_cone) return std::nullopt;
  return p;
}

namespace {

using CellKey = std::array<long long, 3>;

// The cube of edge `cell` (a grid through the origin) holding p.
CellKey cellOf(const Eigen::Vector3d& p, double cell) {
  return {std::llround(std::floor(p.x() / cell)), std::llround(std::floor(p.y() / cell)),
          std::llround(std::floor(p.z() / cell))};
}

// The first of `points` in each cube of edge `cell`, in order.
std::vector<Eigen::Vector3d> onePerCell(const std::vector<Eigen::Vector3d>& points, double cell) {
  std::set<CellKey> seen;
  std::vector<Eigen::Vector3d> out;
  for (const Eigen::Vector3d& p : points)
    if (seen.insert(cellOf(p, cell)).second) out.push_back(p);
  return out;
}

}  // namespace

SamplerKind defaultSamplerKind(const HandModel& hand) {
  return jawGeometry(hand) ? SamplerKind::kAntipodalPalm : SamplerKind::kMixed;
}

SamplerKind samplerKindOf(const SamplerOptions& options) {
  if (options.kind) return *options.kind;
  const bool jaws = options.jaws && !options.finger_points.empty();
  return jaws ? SamplerKind::kAntipodalPalm : SamplerKind::kMixed;
}

Sampler::Sampler(ObjectModel object, const SamplerOptions& options)
    : object_(std::move(object)), options_(options) {
  options_.validate();
  options_.kind = samplerKindOf(options_);
  if (options_.kind == SamplerKind::kAntipodal && !options_.jaws)
    throw Error(
        "the antipodal sampler needs a parallel-jaw hand (two fingers whose pads face each "
        "other); use --sampler mixed, surface or volume for this hand");
  if (options_.kind == SamplerKind::kEnclose && options_.finger_points.empty())
    throw Error(
        "the enclose sampler needs the points of the hand's open fingers (openFingerPoints); "
        "the hand has no finger links with collision shapes: use --sampler mixed");
  if (options_.kind == SamplerKind::kAntipodalPalm &&
      (!options_.jaws || options_.finger_points.empty()))
    throw Error(
        "the antipodal_palm sampler needs a parallel-jaw hand (two fingers whose pads face each "
        "other) with finger collision shapes (SamplerOptions::jaws and finger_points); use "
        "--sampler mixed, surface or volume for this hand");
  if (options_.kind == SamplerKind::kPalmEnclose &&
      (!options_.enclose || options_.finger_points.empty()))
    throw Error(
        "the palm_enclose sampler needs a hand with at least two fingers that close across its "
        "approach axis, with finger collision shapes (SamplerOptions::enclose and "
        "finger_points); use --sampler mixed or enclose for this hand");
  if (options_.kind == SamplerKind::kAntipodalPalm)
    clearance_points_ = onePerCell(options_.finger_points, kClearanceCell);
  groupFingerPoints();
  const bool probed =
      options_.kind == SamplerKind::kAntipodalPalm || options_.kind == SamplerKind::kPalmEnclose;
  attempts_ = probed ? probeAttempts() : options_.attempts;
}

void Sampler::groupFingerPoints() {
  std::map<CellKey, std::size_t> index;
  for (const Eigen::Vector3d& p : options_.finger_points) {
    const auto [it, added] = index.emplace(cellOf(p, kGroupCell), finger_groups_.size());
    if (added) finger_groups_.emplace_back();
    finger_groups_[it->second].points.push_back(p);
  }
  for (FingerGroup& g : finger_groups_) {
    Eigen::Vector3d lo = g.points.front(), hi = lo;
    for (const Eigen::Vector3d& p : g.points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    g.centre = 0.5 * (lo + hi);
    for (const Eigen::Vector3d& p : g.points) g.radius = std::max(g.radius, (p - g.centre).norm());
    g.radius += 1e-9;  // every point strictly inside the ball
  }
}

SamplerKind Sampler::kindOfTrial(std::uint64_t trial) const {
  // No attempts in force (only the probe of antipodal_palm and palm_enclose sets 0; options
  // need >= 1): the mixed sampler's trials.
  const bool mixed = options_.kind == SamplerKind::kMixed || attempts_ == 0;
  if (!mixed) return *options_.kind;
  return trial % 2 == 0 ? SamplerKind::kVolume : SamplerKind::kSurface;
}

Eigen::Quaterniond alignAxis(const Eigen::Vector3d& axis, const Eigen::Vector3d& direction,
                             double roll) {
  const Eigen::Quaterniond align = Eigen::Quaterniond::FromTwoVectors(axis, direction);
  const Eigen::Quaterniond spin(Eigen::AngleAxisd(roll, direction));
  return (spin * align).normalized();
}

Pose Sampler::surfacePose(Rng& rng) const {
  const SurfaceSample s = object_.sampleSurface(rng);
  const double roll = rng.uniform(0.0, 2.0 * M_PI);
  const double standoff = rng.uniform(options_.standoff_min, options_.standoff_max);
  Pose pose;
  pose.orientation = alignAxis(options_.approach_axis, -s.normal, roll);
  pose.position = s.point + standoff * s.normal;
  return pose;
}

std::optional<AntipodalPair> Sampler::drawPair(Rng& rng) const {
  const JawGeometry& jaws = *options_.jaws;
  const double min_w = std::max(jaws.closed_width, 0.0) + options_.width_margin;
  const double max_w = jaws.open_width - options_.width_margin;
  if (max_w <= min_w) return std::nullopt;
  for (int k = 0; k < options_.attempts; ++k) {
    std::optional<AntipodalPair> p =
        antipodalAttempt(object_, rng, options_.friction, min_w, max_w);
    if (p) return p;
  }
  return std::nullopt;
}

// Palm orientation R maps the palm-frame closing axis c onto the pair's axis u and the approach
// axis a onto a direction across u at angle `spin`; the pads' midpoint goes to the pair's.
Pose Sampler::jawPose(const AntipodalPair& pair, double spin) const {
  const JawGeometry& jaws = *options_.jaws;
  const Eigen::Vector3d a = options_.approach_axis;
  const Eigen::Vector3d c = (jaws.closing_axis - jaws.closing_axis.dot(a) * a).normalized();
  const Eigen::Vector3d u = (pair.p2 - pair.p1).normalized();
  const Eigen::Vector3d e1 = u.unitOrthogonal(), e2 = u.cross(e1);
  const Eigen::Vector3d w = std::cos(spin) * e1 + std::sin(spin) * e2;
  Eigen::Matrix3d palm, world;
  palm << c, a, c.cross(a);
  world << u, w, u.cross(w);
  const Eigen::Matrix3d r = world * palm.transpose();
  Pose pose;
  pose.orientation = Eigen::Quaterniond(r).normalized();
  pose.position = 0.5 * (pair.p1 + pair.p2) - r * jaws.pad_midpoint;
  return pose;
}

bool Sampler::fingersOutside(const Pose& palm, double clearance) const {
  const Eigen::Matrix3d r = palm.orientation.toRotationMatrix();
  for (const FingerGroup& g : finger_groups_) {
    if (g.points.size() >= kGroupTestMin) {
      const Eigen::Vector3d c = palm.position + r * g.centre;
      if (!object_.contains(c) && !object_.nearSurface(c, g.radius)) continue;
    }
    for (const Eigen::Vector3d& p : g.points)
      if (object_.contains(palm.position + r * p)) return false;
  }
  if (clearance > 0.0)
    for (const Eigen::Vector3d& p : clearance_points_)
      if (object_.nearSurface(palm.position + r * p, clearance)) return false;
  return true;
}

// Fingertip grasps (place_palm false): the pads on the pair, accepted when no finger point is
// inside.
std::optional<Pose> Sampler::palmJawPose(const AntipodalPair& pair, double spin) const {
  const Pose pose = jawPose(pair, spin);
  if (!fingersOutside(pose, kJawFingerClearance)) return std::nullopt;
  return pose;
}

// Rays in the plane of the palm's front, from the point `face` (object frame, in front of the
// pads' midpoint) to the palm's extent along the closing axis and across it: none may meet
// the surface (a part wider than the hand's opening would pass through the palm).
bool Sampler::palmFaceClear(const Pose& pose, const Eigen::Vector3d& face) const {
  const JawGeometry& jaws = *options_.jaws;
  const Eigen::Vector3d a = options_.approach_axis, c = jaws.closing_axis, v = c.cross(a);
  const Eigen::Vector2d m(c.dot(jaws.pad_midpoint), v.dot(jaws.pad_midpoint));
  const Eigen::Vector3d axes[2] = {pose.orientation * c, pose.orientation * v};
  for (int k = 0; k < 2; ++k) {
    const double reach[2] = {jaws.palm_max[k] - m[k], m[k] - jaws.palm_min[k]};
    for (int side = 0; side < 2; ++side) {
      if (!(reach[side] > 0.0)) continue;
      const Eigen::Vector3d d = side == 0 ? axes[k] : Eigen::Vector3d(-axes[k]);
      if (object_.castRay(face, d, 0.0, reach[side])) return false;
    }
  }
  return true;
}

// Palm grasps: the palm's front on the surface point q, the approach w = -n(q); for a closing
// direction c across w, the pads at depth d ahead of the palm's front (a·m - palm_front). The
// jaws must span the object there: from the probe point x = q + min(d, t/2) w (t = `through`:
// where the ray from q along w leaves the solid) the rays along +c and -c leave it at p2 and p1,
// with min_w <= |p2 - p1| <= max_w and both normals in the friction cones about the axis (the
// antipodal condition at the pads' depth). The pads' midpoint then sits at depth d on the line
// through (p1 + p2) / 2 along w. Accepted when the palm's face is clear and no finger point is
// inside.
std::optional<std::pair<AntipodalPair, Pose>> Sampler::palmFirstAttempt(const SurfaceSample& q,
                                                                        double through, double roll,
                                                                        double min_w,
                                                                        double max_w) const {
  const JawGeometry& jaws = *options_.jaws;
  const Eigen::Vector3d a = options_.approach_axis;
  const Eigen::Vector3d w = -q.normal;
  const Eigen::Vector3d e1 = w.unitOrthogonal(), e2 = w.cross(e1);
  Eigen::Vector3d c = std::cos(roll) * e1 + std::sin(roll) * e2;
  const double depth = palmDepth(jaws, a);
  const Eigen::Vector3d x = q.point + std::min(depth, 0.5 * through) * w;
  // The drawn closing direction finds a wall; the closing axis then turns onto that wall's
  // normal (across w), so that the pads face it.
  const std::optional<RayHit> probe = object_.castRay(x, c, 0.0, max_w);
  if (!probe) return std::nullopt;
  c = probe->normal - probe->normal.dot(w) * w;
  if (!(c.norm() > 0.5)) return std::nullopt;
  c.normalize();
  // A part wider than the opening is rejected by the first ray that runs past the rest of it:
  // the second ray only searches the width the first left.
  const std::optional<RayHit> plus = object_.castRay(x, c, 0.0, max_w);
  if (!plus) return std::nullopt;
  const std::optional<RayHit> minus = object_.castRay(x, -c, 0.0, max_w - plus->distance);
  if (!minus) return std::nullopt;
  const double width = plus->distance + minus->distance;
  const double cos_cone = 1.0 / std::sqrt(1.0 + options_.friction * options_.friction);
  if (width < min_w || width > max_w || plus->normal.dot(c) < cos_cone ||
      -minus->normal.dot(c) < cos_cone)
    return std::nullopt;
  const AntipodalPair pair{minus->point, minus->normal, plus->point, plus->normal};
  // Palm orientation: closing axis onto c, approach onto w.
  const Eigen::Vector3d cp = (jaws.closing_axis - jaws.closing_axis.dot(a) * a).normalized();
  Eigen::Matrix3d palm, world;
  palm << cp, a, cp.cross(a);
  world << c, w, c.cross(w);
  const Eigen::Matrix3d r = world * palm.transpose();
  const Eigen::Vector3d centre = 0.5 * (pair.p1 + pair.p2);
  Pose pose;
  pose.orientation = Eigen::Quaterniond(r).normalized();
  pose.position = centre + (depth - (centre - q.point).dot(w)) * w - r * jaws.pad_midpoint;
  if (!palmFaceClear(pose, q.point - kPalmClearance * w)) return std::nullopt;
  if (!fingersOutside(pose, kJawFingerClearance)) return std::nullopt;
  return std::make_pair(pair, pose);
}

// One attempt draws its numbers whether accepted or not: palm grasps a surface point and a
// roll, trying kSpins rolls evenly spaced from it; fingertip grasps an antipodal attempt and a
// spin, trying kSpins spins likewise.
std::optional<std::pair<AntipodalPair, Pose>> Sampler::palmJawAttempt(Rng& rng, double min_w,
                                                                      double max_w) const {
  if (options_.place_palm) {
    const SurfaceSample q = object_.sampleSurface(rng);
    const double roll = rng.uniform(0.0, 2.0 * M_PI);
    // Where the ray from q along the approach leaves the solid: once per point, for every spin.
    if (!(palmDepth(*options_.jaws, options_.approach_axis) > 0.0)) return std::nullopt;
    const std::optional<RayHit> through = object_.castRay(q.point, -q.normal, kRayStart);
    if (!through) return std::nullopt;
    for (int j = 0; j < kSpins; ++j) {
      auto drawn = palmFirstAttempt(q, through->distance, roll + M_PI * j / kSpins, min_w, max_w);
      if (drawn) return drawn;
    }
    return std::nullopt;
  }
  const std::optional<AntipodalPair> p =
      antipodalAttempt(object_, rng, options_.friction, min_w, max_w);
  const double spin = rng.uniform(0.0, 2.0 * M_PI);
  if (!p) return std::nullopt;
  for (int j = 0; j < kSpins; ++j) {
    const std::optional<Pose> pose = palmJawPose(*p, spin + 2.0 * M_PI * j / kSpins);
    if (pose) return std::make_pair(*p, *pose);
  }
  return std::nullopt;
}

std::optional<std::pair<AntipodalPair, Pose>> Sampler::drawPalmJaw(Rng& rng) const {
  const JawGeometry& jaws = *options_.jaws;
  const double min_w = std::max(jaws.closed_width, 0.0) + options_.width_margin;
  const double max_w = jaws.open_width - options_.width_margin;
  if (max_w <= min_w) return std::nullopt;
  for (int k = 0; k < attempts_; ++k) {
    auto drawn = palmJawAttempt(rng, min_w, max_w);
    if (drawn) return drawn;
  }
  return std::nullopt;
}

// The probe: kProbeAttempts attempts from generators of their own (not the trials'), the same
// for every seed and thread. With p the accepted share, a trial finds a pose within n attempts
// with probability 1 - (1 - p)^n; when that stays under kProbeMinFound at n = options.attempts
// (an object that the jaws almost never span, a mug wider than the opening or the hand's
// span), attempting costs more than it finds: no attempt, the mixed sampler's trials instead.
// antipodal_palm and palm_enclose (one attempt: one surface point, its kEncloseRolls directions).
int Sampler::probeAttempts() const {
  double min_w = 0.0, max_w = 0.0;
  if (options_.kind == SamplerKind::kAntipodalPalm) {
    const JawGeometry& jaws = *options_.jaws;
    min_w = std::max(jaws.closed_width, 0.0) + options_.width_margin;
    max_w = jaws.open_width - options_.width_margin;
    if (max_w <= min_w) return 0;
  }
  const auto attempt = [&](Rng& rng) {
    if (options_.kind == SamplerKind::kPalmEnclose)
      return drawPalmEnclose(object_, *options_.enclose, options_.approach_axis,
                             options_.finger_points, 1, options_.enclose_margin, rng)
          .has_value();
    return palmJawAttempt(rng, min_w, max_w).has_value();
  };
  int accepted = 0;
  for (int k = 0; k < kProbeAttempts; ++k) {
    Rng rng(kProbeSeed, static_cast<std::uint64_t>(k));
    if (attempt(rng)) ++accepted;
  }
  const double p = static_cast<double>(accepted) / kProbeAttempts;
  const double found = 1.0 - std::pow(1.0 - p, options_.attempts);
  return found >= kProbeMinFound ? options_.attempts : 0;
}

std::optional<AntipodalPair> Sampler::antipodalPair(std::uint64_t seed, std::uint64_t trial) const {
  const SamplerKind kind = kindOfTrial(trial);
  Rng rng(seed, trial);
  if (kind == SamplerKind::kAntipodal) return drawPair(rng);
  if (kind != SamplerKind::kAntipodalPalm) return std::nullopt;
  const auto drawn = drawPalmJaw(rng);
  if (!drawn) return std::nullopt;
  return drawn->first;
}

Pose Sampler::sample(std::uint64_t seed, std::uint64_t trial) const {
  Rng rng(seed, trial);
  const SamplerKind kind = kindOfTrial(trial);
  if (kind == SamplerKind::kVolume) {
    Pose pose;
    pose.position = object_.sampleInside(rng);
    pose.orientation = rng.rotation();
    return pose;
  }
  if (kind == SamplerKind::kAntipodal) {
    const std::optional<AntipodalPair> pair = drawPair(rng);
    if (pair) return jawPose(*pair, rng.uniform(0.0, 2.0 * M_PI));
  }
  if (kind == SamplerKind::kAntipodalPalm) {
    const auto drawn = drawPalmJaw(rng);
    if (drawn) return drawn->second;
  }
  if (kind == SamplerKind::kPalmEnclose) {
    const std::optional<Pose> pose =
        drawPalmEnclose(object_, *options_.enclose, options_.approach_axis, options_.finger_points,
                        attempts_, options_.enclose_margin, rng);
    if (pose) return *pose;
  }
  if (kind == SamplerKind::kEnclose) {
    // Each attempt draws a point and a roll; the palm origin sits on the surface.
    for (int k = 0; k < options_.attempts; ++k) {
      const SurfaceSample s = object_.sampleSurface(rng);
      Pose pose;
      pose.orientation = alignAxis(options_.approach_axis, -s.normal, rng.uniform(0.0, 2.0 * M_PI));
      pose.position = s.point;
      if (fingersOutside(pose)) return pose;
    }
  }
  return surfacePose(rng);
}

}  // namespace taskmap
