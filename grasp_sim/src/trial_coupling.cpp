// Trial: coupled closing. A coupled mechanism (sim_model.hpp: a closing joint whose links lie
// on two or more fingers, e.g. a <mimic> jaw pair, or a sidecar "coupled" group) does not stop
// when its first jaw touches: the hand shifts so that the touching (held) jaw stays in place
// while the mechanism keeps closing, until a jaw of another finger touches (the arm's
// compliance centring a parallel gripper). Semantics and equations in grasp_simulator.hpp and
// docs/METHOD.md.
#include <algorithm>
#include <cmath>
#include <limits>

#include "trial.hpp"

namespace taskmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// A link touching when the shift starts (or stops during it) blocks the shift once pressed
/// this many tolerances deeper than it was (a free link blocks when it touches).
constexpr double kFloorMargin = 2.0;
/// A triangle lies ahead of the shift when its outward normal is more than 60 degrees against
/// the shift direction (cosine below -0.5).
constexpr double kOpposing = 0.5;

}  // namespace

bool Trial::heldLink(int l) const {
  if (shift_group_ < 0) return false;
  const auto u = static_cast<std::size_t>(l);
  if (!m_.group_moves[static_cast<std::size_t>(shift_group_)][u]) return false;
  if (l == held_link_) return true;
  return held_finger_ >= 0 && m_.hand.links()[u].finger == held_finger_;
}

// Exact signed distance (deepest EPA depth when penetrating) of a link to the object; +inf
// beyond the tolerance. With `facing_shift`, only triangles the link presses through their face
// and whose outward normal opposes the shift count: a palm sliding along the face it rests on is
// not blocked by it (nor by the side faces under it), a wall ahead is.
double Trial::exactDistance(int l, const Eigen::Isometry3d& t, bool facing_shift) {
  ++st_.queries;
  // Pressed through the face (not a side face under a link resting on a neighbour face) and
  // facing the shift. The baseline scene scans every hit, the culled one searches by branch and
  // bound.
  FacingFilter f;
  f.opposing = kOpposing;
  f.min_agreement = kMinNormalAgreement;
  if (facing_shift) f.away = shift_vel_.normalized();
  return m_.scene->linkNearest(l, t, tol_, facing_shift ? &f : nullptr);
}

// While the hand shifts: the links that do not close (palm, stopped fingers; only what lies
// ahead of the shift) and the held jaw (everything), each measured from its floor
// (dist_ = distance - floor; <= tol blocks the shift).
double Trial::evalStill() {
  double mn = kInf;
  for (int l : m_.shaped) {
    if (moving(l) && !heldLink(l)) continue;
    const auto u = static_cast<std::size_t>(l);
    dist_[u] = exactDistance(l, world_[u], !heldLink(l)) - floor_[u];
    mn = std::min(mn, dist_[u]);
  }
  return mn;
}

// Palm velocity per unit closing time that keeps the held contact point in place: minus the
// point's velocity under the mechanism's active joints, across the approach axis only.
Eigen::Vector3d Trial::shiftVelocity() const {
  const auto& closing = m_.hand.closing();
  const auto hl = static_cast<std::size_t>(held_link_);
  const Eigen::Vector3d p = palm_ * lp_[hl] * held_point_;
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (int c : m_.groups[static_cast<std::size_t>(shift_group_)]) {
    const auto uc = static_cast<std::size_t>(c);
    if (!active_[uc]) continue;
    v += dir_[uc] * closing[uc].speed *
         pointVelocity(m_.hand, palm_, lp_, held_link_, p, closing[uc].joint);
  }
  v -= a_ * a_.dot(v);
  return -v;
}

// Group events of one step's touching links (before autoGrasp stops the other joints).
void Trial::coupledTouch(const std::vector<int>& touching) {
  if (shift_group_ < 0) {
    shiftFirstTouch(touching);
    return;
  }
  const int g = shift_group_;
  bool blocked = false;
  std::vector<int> jaws = {held_link_};
  for (int l : touching) {
    if (heldLink(l) || !moving(l))
      blocked = true;  // the held jaw or a link that does not close is pressed: jammed
    else if (m_.group_moves[static_cast<std::size_t>(g)][static_cast<std::size_t>(l)])
      jaws.push_back(l);  // another finger of the mechanism touches: centred
  }
  if (jaws.size() > 1)
    completeGroup(g, jaws);
  else if (blocked)
    stopGroup(g, held_link_);
}

// No shift yet: a mechanism whose jaws on two fingers touch at once is done; one touching jaw
// starts the shift (one mechanism shifts at a time; another one stops as in autoGrasp).
void Trial::shiftFirstTouch(const std::vector<int>& touching) {
  const auto& links = m_.hand.links();
  for (std::size_t g = 0; g < m_.groups.size(); ++g) {
    std::vector<int> jaws;
    std::vector<int> fingers;
    for (int l : touching) {
      const auto u = static_cast<std::size_t>(l);
      if (!m_.group_moves[g][u] || !moving(l)) continue;
      bool group_active = false;
      for (int j : m_.hand.linkDrivers()[u]) {
        const int c = m_.closing_of[static_cast<std::size_t>(j)];
        group_active = group_active ||
                       (c >= 0 && m_.group_of[static_cast<std::size_t>(c)] == static_cast<int>(g) &&
                        active_[static_cast<std::size_t>(c)]);
      }
      if (!group_active) continue;
      jaws.push_back(l);
      const int f = links[u].finger >= 0 ? links[u].finger : -1 - l;
      if (std::find(fingers.begin(), fingers.end(), f) == fingers.end()) fingers.push_back(f);
    }
    if (jaws.empty()) continue;
    if (fingers.size() >= 2)
      completeGroup(static_cast<int>(g), jaws);
    else if (shift_group_ < 0)
      startShift(static_cast<int>(g), jaws.front());
    else
      stopGroup(static_cast<int>(g), jaws.front());
  }
}

void Trial::startShift(int g, int l) {
  const auto u = static_cast<std::size_t>(l);
  const Eigen::Isometry3d tl = palm_ * lp_[u];
  std::vector<TriangleHit> hits;
  m_.scene->linkHits(l, tl, tol_, &hits);
  ++st_.queries;
  const TriangleHit* best = nullptr;
  for (const auto& hh : hits)
    if (!best || hh.distance < best->distance) best = &hh;
  held_point_ = best ? Eigen::Vector3d(tl.inverse() * best->point) : Eigen::Vector3d::Zero();
  shift_group_ = g;
  held_link_ = l;
  held_finger_ = m_.hand.links()[u].finger;
  shift_vel_ = shiftVelocity();
  if (!(shift_vel_.norm() > 1e-9)) {  // the jaw closes along the approach axis: no centring
    stopGroup(g, l);
    return;
  }
  for (int k : m_.shaped) {
    const auto uk = static_cast<std::size_t>(k);
    floor_[uk] = 0.0;
    if (moving(k) && !heldLink(k)) continue;
    const double d = exactDistance(k, palm_ * lp_[uk], !heldLink(k));
    if (d <= tol_) floor_[uk] = std::min(d, 0.0) - kFloorMargin * tol_;
  }
}

// Touching links that stopped during the shift (their joints touched) keep their place from now
// on: they block the shift only when pressed deeper than where they stopped.
void Trial::settleStopped(const std::vector<int>& touching) {
  for (int l : touching) {
    const auto u = static_cast<std::size_t>(l);
    if (floor_[u] != 0.0 || moving(l) || heldLink(l)) continue;
    floor_[u] = std::min(dist_[u], 0.0) - kFloorMargin * tol_;
  }
}

// Both jaws (links of two fingers) touch: every joint of the mechanism stops, and the squeeze
// presses every touching jaw.
void Trial::completeGroup(int g, const std::vector<int>& jaws) {
  for (int c : m_.groups[static_cast<std::size_t>(g)]) {
    const auto uc = static_cast<std::size_t>(c);
    if (!active_[uc]) continue;
    active_[uc] = 0;
    stop_link_[uc] = jaws.back();
    press_extra_[uc].assign(jaws.begin(), jaws.end() - 1);
  }
  if (shift_group_ == g) endShift();
}

// The mechanism stops with one jaw in contact (jammed, or no shift possible).
void Trial::stopGroup(int g, int l) {
  for (int c : m_.groups[static_cast<std::size_t>(g)]) {
    const auto uc = static_cast<std::size_t>(c);
    if (!active_[uc]) continue;
    active_[uc] = 0;
    stop_link_[uc] = l;
  }
  if (shift_group_ == g) endShift();
}

void Trial::endShift() {
  shift_group_ = -1;
  held_link_ = -1;
  held_finger_ = -1;
  shift_vel_.setZero();
  std::fill(floor_.begin(), floor_.end(), 0.0);
}

}  // namespace taskmap
