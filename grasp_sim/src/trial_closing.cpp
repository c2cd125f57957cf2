// Trial: closing (GraspIt!'s autoGrasp) and the squeeze. Semantics in grasp_simulator.hpp.
#include <algorithm>
#include <cmath>
#include <limits>

#include "trial.hpp"

namespace taskmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Deepest penetration the squeeze may cause, in multiples of the squeeze distance.
constexpr double kMaxSqueezeFactor = 2.0;
/// Bisection steps when the squeeze has to be scaled back.
constexpr int kSqueezeBisections = 6;

}  // namespace

bool Trial::moving(int l) const {
  for (int j : m_.hand.linkDrivers()[static_cast<std::size_t>(l)]) {
    const int c = m_.closing_of[static_cast<std::size_t>(j)];
    if (c >= 0 && active_[static_cast<std::size_t>(c)]) return true;
  }
  return false;
}

Eigen::VectorXd Trial::advance(const Eigen::VectorXd& from, double dt) const {
  const auto& closing = m_.hand.closing();
  Eigen::VectorXd out = from;
  for (std::size_t c = 0; c < closing.size(); ++c) {
    if (!active_[c]) continue;
    const int j = closing[c].joint;
    const double v = from[j] + dir_[c] * closing[c].speed * dt;
    out[j] = dir_[c] > 0 ? std::min(v, closing[c].target) : std::max(v, closing[c].target);
  }
  return out;
}

// Distances of the moving links at joint values qq (and the palm shifted by dt of a coupled
// closing), to the object and (self-contact stops a link like an object contact) to the hand
// links it may collide with; returns the minimum. While the hand shifts, the links that do not
// close (and the held jaw) count from their floor (evalStill).
double Trial::evalMoving(const Eigen::VectorXd& qq, double dt) {
  m_.hand.linkPoses(qq, &lp_);
  Eigen::Isometry3d pm = palm_;
  const bool shifting = shift_group_ >= 0;
  if (shifting) pm.translation() += dt * shift_vel_;
  for (int l : m_.shaped) {
    const auto u = static_cast<std::size_t>(l);
    world_[u] = pm * lp_[u];
    // linkLinkDistance's first test, once per link: the same arithmetic, so the same answer.
    if (m_.opt.check_self_collision) centre_[u] = m_.scene->linkCentre(l, world_[u]);
  }
  double mn = kInf;
  ++eval_id_;
  for (int l : mov_) {
    if (shifting && heldLink(l)) continue;
    const auto u = static_cast<std::size_t>(l);
    const Eigen::Isometry3d& tl = world_[u];
    double d = 0.0;
    if (m_.lean_queries) {
      SeenTriangles& slot = (*seen_)[u][seen_next_[u]++ % kSeen];
      d = m_.scene->linkDistance(l, tl, tol_, &slot);
    } else {
      d = m_.scene->linkDistance(l, tl, tol_);
    }
    ++st_.queries;
    if (m_.opt.check_self_collision)
      for (std::size_t k = 0; k < m_.partners[u].size(); ++k) {
        const int o = m_.partners[u][k];
        const auto uo = static_cast<std::size_t>(o);
        if ((centre_[u] - centre_[uo]).norm() > m_.radius[u] + m_.radius[uo] + tol_) continue;
        d = std::min(d, pairSelfDistance(l, k));
      }
    dist_[u] = d;
    mn = std::min(mn, d);
  }
  if (shifting) mn = std::min(mn, evalStill());
  ++st_.closing_steps;
  return mn;
}

// The distance of link `link` and its k-th self-collision partner at this evaluation's poses
// (world_), linkLinkDistance with the pair's carried axis. When the partner's own call in this
// evaluation proved the pair apart without GJK (its separating axis left a gap above tol_ +
// 1e-9 m, a lower bound of the distance whichever link is asked first), the answer is +inf
// without a second test: GJK in either order is accurate to ~1e-12 m, so it would report no
// distance within tol_ either.
double Trial::pairSelfDistance(int link, std::size_t k) {
  const auto u = static_cast<std::size_t>(link);
  const int o = m_.partners[u][k];
  const auto uo = static_cast<std::size_t>(o);
  const auto back = static_cast<std::size_t>(m_.partner_slot[u][k]);
  if (pair_eval_[uo][back] == eval_id_ && pair_apart_[uo][back]) return kInf;
  bool apart = false;
  const double d =
      m_.scene->linkLinkDistance(link, world_[u], o, world_[uo], tol_,
                                 m_.diag.self_collision_axes ? &pair_axis_[u][k] : nullptr, &apart);
  pair_eval_[u][k] = eval_id_;
  pair_apart_[u][k] = apart;
  return d;
}

// A touching link stops every closing joint that moves it (autoGrasp), except the joints of a
// coupled mechanism, which shift the hand until another of its fingers touches.
void Trial::stopTouching(const std::vector<int>& touching) {
  if (!m_.groups.empty()) coupledTouch(touching);
  for (int l : touching)
    for (int j : m_.hand.linkDrivers()[static_cast<std::size_t>(l)]) {
      const int c = m_.closing_of[static_cast<std::size_t>(j)];
      if (c < 0 || !active_[static_cast<std::size_t>(c)]) continue;
      if (shift_group_ >= 0 && m_.group_of[static_cast<std::size_t>(c)] == shift_group_) continue;
      active_[static_cast<std::size_t>(c)] = 0;
      stop_link_[static_cast<std::size_t>(c)] = l;
    }
  if (shift_group_ >= 0) settleStopped(touching);
}

void Trial::refreshMoving() {
  mov_.clear();
  for (int l : m_.shaped)
    if (moving(l)) mov_.push_back(l);
  eval_ = shift_group_ >= 0 ? m_.shaped : mov_;
}

void Trial::close() {
  const auto& closing = m_.hand.closing();
  const std::size_t nc = closing.size();
  active_.assign(nc, 0);
  stop_link_.assign(nc, -1);
  press_extra_.assign(nc, {});
  floor_.assign(m_.hand.links().size(), 0.0);
  dir_.assign(nc, 0.0);
  for (std::size_t c = 0; c < nc; ++c) {
    const double diff = closing[c].target - q_[closing[c].joint];
    dir_[c] = diff > 0 ? 1.0 : -1.0;
    active_[c] = std::abs(diff) > 1e-12;
  }
  world_.assign(m_.hand.links().size(), Eigen::Isometry3d());
  centre_.assign(m_.hand.links().size(), Eigen::Vector3d::Zero());
  pair_axis_.resize(m_.partners.size());
  pair_apart_.resize(m_.partners.size());
  pair_eval_.resize(m_.partners.size());
  for (std::size_t u = 0; u < m_.partners.size(); ++u) {
    pair_axis_[u].assign(m_.partners[u].size(), Eigen::Vector3d::Zero());
    pair_apart_[u].assign(m_.partners[u].size(), 0);
    pair_eval_[u].assign(m_.partners[u].size(), -1);
  }
  // The rings live per thread (their vectors keep their capacity from trial to trial).
  thread_local std::vector<std::array<SeenTriangles, kSeen>> seen;
  seen.resize(std::max(seen.size(), m_.hand.links().size()));
  for (auto& ring : seen)
    for (auto& s : ring) s.complete = false;
  seen_ = &seen;
  seen_next_.assign(m_.hand.links().size(), 0);
  refreshMoving();
  evalMoving(q_);
  std::vector<int> touching;
  for (int l : mov_)
    if (dist_[static_cast<std::size_t>(l)] <= tol_) touching.push_back(l);
  stopTouching(touching);
  while (true) {
    refreshMoving();
    if (mov_.empty()) break;
    if (st_.closing_steps >= m_.opt.max_closing_steps) {
      step_limit_ = true;
      break;
    }
    closingStep();
  }
  m_.hand.linkPoses(q_, &lp_);
}

// One coarse closing step: no point of a moving link moves more than half its thickness (or
// the closing joints reach their limits); a step into penetration is bisected.
void Trial::closingStep() {
  const auto& closing = m_.hand.closing();
  const auto& levers = m_.hand.jointLevers();
  // `rate` bounds the speed (metres per unit time) of every point of every moving link, except
  // for a link that one driver turns through two joints of the same sense (the humanoid's
  // middle and distal phalanges): HandModel::jointLevers() keeps a driver's largest single lever,
  // not their sum, so there the bound falls short by up to the second joint's lever (about 1.4x
  // on the humanoid's distal links; docs/METHOD.md §2). Changing it changes those hands' maps.
  double rate = 0.0, dt_lim = kInf, dt_step = kInf;
  for (std::size_t c = 0; c < closing.size(); ++c) {
    if (!active_[c]) continue;
    const int j = closing[c].joint;
    dt_lim = std::min(dt_lim, std::abs(closing[c].target - q_[j]) / closing[c].speed);
  }
  const double shift_speed = shift_group_ >= 0 ? shift_vel_.norm() : 0.0;
  for (int l : eval_) {
    double link_rate = shift_speed;
    for (int j : m_.hand.linkDrivers()[static_cast<std::size_t>(l)]) {
      const int c = m_.closing_of[static_cast<std::size_t>(j)];
      if (c >= 0 && active_[static_cast<std::size_t>(c)])
        link_rate +=
            closing[static_cast<std::size_t>(c)].speed * levers[static_cast<std::size_t>(j)];
    }
    rate = std::max(rate, link_rate);
    const double h = std::clamp(0.5 * m_.thickness[static_cast<std::size_t>(l)], 2.0 * tol_, 0.02);
    dt_step = std::min(dt_step, h / std::max(link_rate, 1e-12));
  }
  const double dt = std::min(dt_step, dt_lim);
  const Eigen::VectorXd q1 = advance(q_, dt);
  const double m1 = evalMoving(q1, dt);
  std::vector<int> touching;
  if (m1 < 0.0) {
    bisectStep(dt, rate, &touching);
  } else {
    q_ = q1;
    if (shift_group_ >= 0) {
      palm_.translation() += dt * shift_vel_;
      st_.centring_shift += dt * shift_speed;
    }
    for (int l : eval_)
      if (dist_[static_cast<std::size_t>(l)] <= tol_) touching.push_back(l);
  }
  stopTouching(touching);
  for (std::size_t c = 0; c < closing.size(); ++c)
    if (active_[c] && std::abs(q_[closing[c].joint] - closing[c].target) <= 1e-12) active_[c] = 0;
  if (shift_group_ >= 0) {
    bool any = false;
    for (int c : m_.groups[static_cast<std::size_t>(shift_group_)])
      any = any || active_[static_cast<std::size_t>(c)];
    if (!any)
      endShift();
    else
      shift_vel_ = shiftVelocity();
  }
}

// Bisection on a step that ends in penetration: lo is free (moving links > tol apart at its
// start), hi penetrates. Ends when a free state touches, or when the Lipschitz bound
// rate * (hi - lo) <= tol proves that the links penetrating at hi are within tol of contact at lo.
void Trial::bisectStep(double dt, double rate, std::vector<int>* touching) {
  double lo = 0.0, hi = dt;
  std::vector<double> dist_lo(dist_.size(), kInf), dist_hi = dist_;
  bool touching_lo = false;
  while ((hi - lo) * rate > tol_ && st_.closing_steps < m_.opt.max_closing_steps) {
    const double mid = 0.5 * (lo + hi);
    const double mm = evalMoving(advance(q_, mid), mid);
    if (mm < 0.0) {
      hi = mid;
      dist_hi = dist_;
    } else {
      lo = mid;
      dist_lo = dist_;
      if (mm <= tol_) {
        touching_lo = true;
        break;
      }
    }
  }
  q_ = advance(q_, lo);
  if (shift_group_ >= 0) {
    palm_.translation() += lo * shift_vel_;
    st_.centring_shift += lo * shift_vel_.norm();
  }
  for (int l : eval_) {
    const auto u = static_cast<std::size_t>(l);
    if (dist_lo[u] <= tol_ || (!touching_lo && dist_hi[u] < 0.0)) touching->push_back(l);
  }
  if (shift_group_ >= 0) dist_ = dist_lo;  // the state kept (settleStopped reads it)
  m_.hand.linkPoses(q_, &lp_);
}

// The contacts each contact-stopped closing joint presses: the closest hit of its stopping link
// (and, for a coupled mechanism, of every jaw in contact) on a triangle that faces the link;
// none when the link was stopped by the hand itself.
std::vector<SqueezeContact> Trial::pressingContacts() {
  const auto& closing = m_.hand.closing();
  const CollisionScene& scene = *m_.scene;
  std::vector<SqueezeContact> pressing;
  for (std::size_t c = 0; c < closing.size(); ++c) {
    std::vector<int> links = press_extra_[c];
    if (stop_link_[c] >= 0) links.insert(links.begin(), stop_link_[c]);
    for (int l : links) {
      // The closest hit on a facing triangle, first in linkHits' order among equals (the
      // baseline scene scans every hit, the culled one searches by branch and bound).
      FacingFilter facing;
      facing.any_direction = true;
      facing.min_agreement = kMinNormalAgreement;
      TriangleHit best;
      ++st_.queries;
      const Eigen::Isometry3d pose = palm_ * lp_[static_cast<std::size_t>(l)];
      // Where the link stopped a closing evaluation saw its triangles within tol_ (lean
      // queries): the same answer without a tree search.
      const SeenTriangles* seen = seenAt(l, pose);
      const double gap = seen ? scene.linkNearest(l, pose, tol_, &facing, &best, *seen)
                              : scene.linkNearest(l, pose, tol_, &facing, &best);
      if (!(gap < kInf)) continue;
      SqueezeContact sc;
      sc.joint = closing[c].joint;
      sc.link = l;
      sc.point = best.point;
      sc.normal = scene.faceNormal(best.triangle);
      sc.gap = best.distance;
      sc.dir = dir_[c];
      sc.target = closing[c].target;
      pressing.push_back(sc);
    }
  }
  return pressing;
}

// The complete record of a closing evaluation of `link` at `pose` (bit for bit) and tol_, or
// null.
const SeenTriangles* Trial::seenAt(int link, const Eigen::Isometry3d& pose) const {
  if (!seen_) return nullptr;
  for (const SeenTriangles& s : (*seen_)[static_cast<std::size_t>(link)])
    if (s.answers(link, pose, tol_)) return &s;
  return nullptr;
}

// True when a squeezed link at joint values qq presses a facing triangle deeper than `limit`.
bool Trial::squeezedTooDeep(const std::vector<int>& squeezed, const Eigen::VectorXd& qq,
                            double limit) {
  if (!m_.lean_queries) return deepestSqueezed(squeezed, qq) > limit;
  const auto poses = m_.hand.linkPoses(qq);
  for (int l : squeezed) {
    ++st_.queries;
    if (m_.scene->linkPressesDeeper(l, palm_ * poses[static_cast<std::size_t>(l)], tol_, limit,
                                    kMinNormalAgreement))
      return true;
  }
  return false;
}

double Trial::deepestSqueezed(const std::vector<int>& squeezed, const Eigen::VectorXd& qq) {
  const auto poses = m_.hand.linkPoses(qq);
  double deep = 0.0;
  for (int l : squeezed) {
    std::vector<TriangleHit> hits;
    m_.scene->linkHits(l, palm_ * poses[static_cast<std::size_t>(l)], tol_, &hits);
    ++st_.queries;
    for (const auto& hh : hits)
      if (hh.normal.dot(m_.scene->faceNormal(hh.triangle)) >= kMinNormalAgreement)
        deep = std::max(deep, -hh.distance);
  }
  return deep;
}

// The squeeze is first order and moves whole chains: a link farther out on a squeezed chain may
// press much deeper than its own contact. Scale the squeeze back (bisection) until no link moved
// by it presses deeper than kMaxSqueezeFactor * squeeze + tolerance.
void Trial::limitSqueeze(const Eigen::VectorXd& q_contact) {
  std::vector<int> squeezed;
  for (int l : m_.shaped)
    for (int j : m_.hand.linkDrivers()[static_cast<std::size_t>(l)])
      if (q_[j] != q_contact[j]) {
        squeezed.push_back(l);
        break;
      }
  const double limit = kMaxSqueezeFactor * m_.squeeze + tol_;
  if (squeezed.empty() || !squeezedTooDeep(squeezed, q_, limit)) return;
  const Eigen::VectorXd full = q_ - q_contact;
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < kSqueezeBisections; ++it) {
    const double mid = 0.5 * (lo + hi);
    (squeezedTooDeep(squeezed, q_contact + mid * full, limit) ? hi : lo) = mid;
  }
  q_ = q_contact + lo * full;
}

void Trial::squeeze() {
  if (m_.squeeze > 0.0) {
    const std::vector<SqueezeContact> pressing = pressingContacts();
    const Eigen::VectorXd q_contact = q_;
    applySqueeze(m_.hand, palm_, lp_, pressing, m_.squeeze, &q_);
    limitSqueeze(q_contact);
    m_.hand.linkPoses(q_, &lp_);
  }
  if (m_.diag.profile) st_.close_seconds = lap();
}

}  // namespace taskmap
