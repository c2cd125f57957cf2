// Self-collision pairs that can never come within the contact tolerance (docs/METHOD.md §2,
// "Self-collision pairs proven apart over their joint's range").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "sim_model.hpp"

namespace taskmap {
namespace {

/// Relative accuracy allowed to a GJK distance (an upper bound of the true one: the distance of
/// two points on the shapes; Bullet's float64 GJK stops at 1e-12 relative), and an absolute
/// margin, metres: far above rounding.
constexpr double kGjkRelative = 1e-3;
constexpr double kMargin = 1e-9;
/// Samples per pair before giving up (then the pair stays).
constexpr int kMaxSamples = 4096;

/// An upper bound of the speed (metres per unit of actuated joint `act`) of any point of link
/// `l` relative to the palm, when only `act` moves: over the joints from `l` up to the root
/// driven by `act`, |multiplier| times the distance from the joint's origin to the link's
/// farthest point (the joint offsets below it and the shapes' extent), 1 per unit for prismatic.
double pointSpeed(const HandModel& hand, int l, int act) {
  const auto& links = hand.links();
  const auto& joints = hand.joints();
  double extent = 0.0;  // from the current link frame's origin to link l's farthest point
  for (const auto& s : links[static_cast<std::size_t>(l)].shapes)
    extent = std::max(extent, s.origin.translation().norm() + s.boundingRadius());
  double speed = 0.0;
  int cur = l;
  while (links[static_cast<std::size_t>(cur)].parent_joint >= 0) {
    const HandJoint& j =
        joints[static_cast<std::size_t>(links[static_cast<std::size_t>(cur)].parent_joint)];
    if (j.driver == act && j.type != JointType::kFixed)
      speed += std::abs(j.multiplier) * (j.type == JointType::kPrismatic ? 1.0 : extent);
    extent += j.origin.translation().norm();
    if (j.type == JointType::kPrismatic) extent += std::max(std::abs(j.lower), std::abs(j.upper));
    cur = j.parent_link;
  }
  return speed;
}

/// True when links a and b, whose relative pose only actuated joint `act` changes, are farther
/// apart than `tol` at every value of `act` within its limits: samples from the lower limit
/// on, each covering the values within (lower bound of its distance - tol - margin) / speed of
/// it, where speed bounds how fast the distance changes.
bool apartOverRange(const SimModel& m, int a, int b, int act, double tol) {
  const double speed = pointSpeed(m.hand, a, act) + pointSpeed(m.hand, b, act);
  const double lo = m.hand.lowerLimits()[act], hi = m.hand.upperLimits()[act];
  Eigen::VectorXd q = m.hand.preshape();
  std::vector<Eigen::Isometry3d> poses;
  double x = lo;
  for (int n = 0; n < kMaxSamples; ++n) {
    q[act] = x;
    m.hand.linkPoses(q, &poses);
    constexpr double kFar = 1.0;  // metres: GJK on every shape pair
    const double d = m.scene->linkLinkDistance(a, poses[static_cast<std::size_t>(a)], b,
                                               poses[static_cast<std::size_t>(b)], kFar);
    const double lower = std::isinf(d) ? kFar : d * (1.0 - kGjkRelative) - kMargin;
    const double spare = lower - tol - kMargin;
    if (!(spare > 0.0)) return false;
    if (x >= hi || !(speed > 0.0)) return true;
    x = std::min(hi, x + spare / speed);
  }
  return false;
}

}  // namespace

void dropPairsProvenApart(SimModel* m) {
  const auto& drivers = m->hand.linkDrivers();
  const double tol = m->opt.contact_tolerance;
  std::vector<std::pair<int, int>> kept;
  for (const auto& [a, b] : m->self_pairs) {
    std::vector<int> both = drivers[static_cast<std::size_t>(a)];
    both.insert(both.end(), drivers[static_cast<std::size_t>(b)].begin(),
                drivers[static_cast<std::size_t>(b)].end());
    std::sort(both.begin(), both.end());
    both.erase(std::unique(both.begin(), both.end()), both.end());
    if (both.size() == 1 && apartOverRange(*m, a, b, both[0], tol)) continue;
    kept.emplace_back(a, b);
  }
  if (std::getenv("TM_DBG"))
    std::fprintf(stderr, "self pairs %zu -> %zu\n", m->self_pairs.size(), kept.size());
  m->self_pairs = kept;
}

}  // namespace taskmap
