// Trial: construction, retraction, palm placement, contacts and the verdict. Closing and squeeze
// are in trial_closing.cpp. Semantics are documented in grasp_simulator.hpp.
#include "trial.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "taskmap/grasp_sim/contact_manifold.hpp"

namespace taskmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Contacts of one link closer than this are merged (the deepest is kept), metres.
constexpr double kMergeRadius = 1e-3;
/// |a - b| < kMergeRadius, computed as Eigen's norm() compares it (sqrt of the squared norm),
/// with the square root taken only near the radius (sqrt is monotone: the same answer).
bool withinMergeRadius(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double sq = (a - b).squaredNorm();
  if (sq < 0.81 * kMergeRadius * kMergeRadius) return true;
  if (sq > 1.21 * kMergeRadius * kMergeRadius) return false;
  return std::sqrt(sq) < kMergeRadius;
}
/// Lean contact queries: hits within this distance, metres (all penetrating ones; the planes
/// cull a triangle only beyond it plus 1e-9, where GJK cannot report a penetration).
constexpr double kPenetrating = 1e-9;
/// Lean queries cull a triangle by a bound only this far beyond the threshold, metres: a
/// separating-axis or plane bound may exceed GJK's distance by rounding (~1e-18 m).
constexpr double kBoundSlack = 1e-9;
/// Fingertip grasps: most back-off steps toward the standoff (each closes most of the gap).
constexpr int kMaxStandoffSteps = 20;
/// Fingertip grasps: farthest palm gap GraspStats::palm_gap measures, metres.
constexpr double kPalmGapRange = 0.1;
/// palmStaysClear proves the palm farther than the tolerance plus this, metres (far above the
/// rounding of the queries' distances, ~1e-12 m).
constexpr double kSweepSlack = 1e-6;

}  // namespace

Trial::Trial(const SimModel& model, const Pose& initial, bool status_only)
    : m_(model),
      tol_(model.opt.contact_tolerance),
      status_only_(status_only),
      // placePalm then ends a palm-less retraction with no_palm_contact, and the automatic
      // retraction limit leaves the hand 1 cm beyond the object (retract): never not_retractable.
      early_no_palm_(status_only && model.grasp_mode == GraspMode::kPalm &&
                     model.opt.require_palm_contact && model.opt.max_retraction == 0.0),
      st_(res_.stats) {
  if (m_.diag.profile) t0_ = Clock::now();
  palm_ = initial.toIsometry();
  p0_ = palm_.translation();
  a_ = (palm_.linear() * m_.hand.approachAxis()).normalized();
  q_ = m_.hand.preshape();
  m_.hand.linkPoses(q_, &lp_);
  dist_.assign(m_.hand.links().size(), kInf);
}

double Trial::lap() {
  const Clock::time_point now = Clock::now();
  const double s = std::chrono::duration<double>(now - t0_).count();
  t0_ = now;
  return s;
}

void Trial::finish(GraspStatus status, const std::string& msg) {
  res_.status = status;
  res_.message = msg;
  Eigen::Isometry3d reported = palm_;
  reported.translation() -= pressed_ * a_;
  res_.pose = Pose::fromIsometry(reported);
  res_.joints = q_;
}

// Signed distance of every shaped link at palm pose `pm` (threshold-limited); -inf when a link
// lies wholly inside the object (checked only when `inside_check`). With `inside_check` the
// evaluation stops at the first penetrating link, trying the last one found first (`dist_` is
// then complete only for collision-free poses).
double Trial::evalAll(const Eigen::Isometry3d& pm, double threshold, bool inside_check) {
  double mn = kInf;
  const auto& shaped = m_.shaped;
  for (std::size_t k = 0; k < shaped.size(); ++k) {
    const std::size_t idx = (first_ + k) % shaped.size();
    const int l = shaped[idx];
    const auto u = static_cast<std::size_t>(l);
    const Eigen::Isometry3d t = pm * lp_[u];
    double d = m_.scene->linkDistance(l, t, threshold);
    ++st_.queries;
    if (inside_check && d == kInf && m_.scene->linkInside(l, t)) d = -kInf;
    dist_[u] = d;
    mn = std::min(mn, d);
    if (inside_check && d < 0.0) {
      first_ = idx;
      break;
    }
  }
  return mn;
}

// Conservative advancement reads only the minimum distance (and placePalm the distances of the
// links within tol_): with lean queries each link is asked within the smallest distance found so
// far plus kBoundSlack (at least tol_, at most `far`), the nearest link of the last call first. The
// minimum and every distance <= tol_ are those of evalAll(pm, far, false); a link farther than its
// threshold reads +inf.
double Trial::evalNearest(const Eigen::Isometry3d& pm, double far) {
  if (!m_.lean_queries) return evalAll(pm, far, false);
  double mn = kInf;
  const auto& shaped = m_.shaped;
  std::size_t nearest = near_;
  for (std::size_t k = 0; k < shaped.size(); ++k) {
    const std::size_t idx = (near_ + k) % shaped.size();
    const int l = shaped[idx];
    const auto u = static_cast<std::size_t>(l);
    const double d =
        m_.scene->linkDistance(l, pm * lp_[u], std::min(far, std::max(mn + kBoundSlack, tol_)));
    ++st_.queries;
    dist_[u] = d;
    if (d < mn) {
      mn = d;
      nearest = idx;
    }
  }
  near_ = nearest;
  return mn;
}

Eigen::Isometry3d Trial::at(double s) const {
  Eigen::Isometry3d pm = palm_;
  pm.translation() = p0_ - s * a_;
  return pm;
}

bool Trial::retract() {
  const double s_max = m_.opt.max_retraction > 0.0
                           ? m_.opt.max_retraction
                           : (p0_ - m_.scene->objectCentre()).norm() + m_.scene->objectRadius() +
                                 m_.hand.reach() + 0.01;
  double s = 0.0;
  const double m = evalAll(at(0.0), tol_, true);
  if (m < 0.0) {
    if (!leaveObject(m, s_max, &s)) return false;
  } else if (m > tol_) {
    if (!approachObject(s_max, &s)) return false;
  }
  palm_ = at(s);
  st_.retraction = s;
  return true;
}

// True when every palm-rigid link, at palm pose at(s) and at every pose moved on from it along
// `dir` (-a_ out of the object, a_ onto it), stays farther than tol_ from the object. Wherever
// the hand then stops touching, the palm is beyond tol_: placePalm's no_palm_contact (or, for
// an approach, no touch at all: no_palm_contact too).
bool Trial::palmStaysClear(double s, const Eigen::Vector3d& dir) const {
  return palmClearFrom(s, dir) < s;
}

// Ends a retraction whose palm provably stays clear from at(s) on: no_palm_contact.
bool Trial::endClear(double s) {
  palm_ = at(s);
  st_.retraction = s;
  finish(GraspStatus::kNoPalmContact,
         "a finger touches the object before the palm when the hand leaves it");
  return false;
}

// palmStaysClear's proof from at(s) along `dir` (-a_ out of the object) with a witness when it
// fails: < s when every palm-rigid link provably stays farther than tol_ from the object from
// at(s) on; else s plus the last u at which the first link the proof fails on may meet its first
// triangle (CollisionScene::linkSweepLast). A proof from any s' before that would find the same
// triangle in its way (the bounds are geometric: moving the start along the line shifts the
// interval, up to rounding), so it is not tried again until the hand has passed that point
// (exact either way: a proof not tried only ends the trial later, with the same status).
double Trial::palmClearFrom(double s, const Eigen::Vector3d& dir) const {
  const Eigen::Isometry3d pm = at(s);
  for (int l : m_.shaped) {
    const auto u = static_cast<std::size_t>(l);
    if (!m_.hand.links()[u].palm) continue;
    const double last = m_.scene->linkSweepLast(l, pm * lp_[u], dir, tol_ + kSweepSlack, true);
    if (last >= 0.0) return s + last;
  }
  return s - 1.0;
}

// palmClearFrom at lo once lo is past the previous witness (`retry`): true when the palm
// provably stays clear from at(lo) on.
bool Trial::palmClearAt(double lo, double* retry) const {
  if (!(lo > *retry)) return false;
  *retry = palmClearFrom(lo, -a_);
  return *retry < lo;
}

// The hand penetrates at s = 0: coarse steps out along -a, then bisection until the free side
// touches within the tolerance. With early_no_palm_ the trial ends as soon as the palm provably
// stays clear of the object from the last penetrating pose on (palmClearAt), before each coarse
// step and after each bisection step that moves that pose.
bool Trial::leaveObject(double m, double s_max, double* s) {
  double lo = 0.0, hi = 0.0;
  double retry = early_no_palm_ ? -1.0 : kInf;  // palmClearAt: the proof's next chance
  while (true) {
    if (palmClearAt(lo, &retry)) return endClear(lo);
    const double step = std::max(m_.retract_step, std::isfinite(m) ? -m : 0.0);
    hi = std::min(lo + step, s_max);
    m = evalAll(at(hi), tol_, true);
    if (m >= 0.0) break;
    lo = hi;
    if (hi >= s_max) {
      palm_ = at(s_max);
      st_.retraction = s_max;
      finish(GraspStatus::kNotRetractable,
             "the hand still penetrates the object after retracting " + std::to_string(s_max) +
                 " m along its approach axis");
      return false;
    }
  }
  // Bisection: lo penetrates, hi is free; stop when the free side touches within tol.
  std::vector<double> dist_hi = dist_;
  while (m > tol_ && hi - lo > 1e-9) {
    const double mid = 0.5 * (lo + hi);
    const double mm = evalAll(at(mid), tol_, true);
    if (mm < 0.0) {
      lo = mid;
      if (palmClearAt(lo, &retry)) return endClear(lo);
    } else {
      hi = mid;
      m = mm;
      dist_hi = dist_;
    }
  }
  dist_ = dist_hi;
  *s = hi;
  return true;
}

// The hand is free at s = 0: advance along +a (conservative advancement) until touching.
bool Trial::approachObject(double s_max, double* s) {
  if (early_no_palm_ && palmStaysClear(0.0, a_)) {
    finish(GraspStatus::kNoPalmContact, "the palm cannot touch the object on its approach axis");
    return false;
  }
  const double far = std::max(4.0 * m_.retract_step, 0.02);
  while (true) {
    const double m = evalNearest(at(*s), far);
    if (m <= tol_) return true;
    const double step = std::isfinite(m) ? m - 0.25 * tol_ : far;
    *s -= step;
    if (-*s > s_max) {
      palm_ = at(*s);
      st_.retraction = *s;
      finish(GraspStatus::kNoPalmContact,
             "the hand touches nothing when advanced along its approach axis");
      return false;
    }
  }
}

bool Trial::placePalm() {
  if (m_.grasp_mode == GraspMode::kFingertip) {
    placeFingertips();
    if (m_.diag.profile) st_.retract_seconds = lap();
    return true;
  }
  bool palm_touch = false;
  double palm_gap = kInf;
  for (int l : m_.shaped) {
    const auto u = static_cast<std::size_t>(l);
    if (m_.hand.links()[u].palm && dist_[u] <= tol_) {
      palm_touch = true;
      palm_gap = std::min(palm_gap, dist_[u]);
    }
  }
  if (m_.diag.profile) st_.retract_seconds = lap();
  if (!palm_touch && m_.opt.require_palm_contact) {
    finish(GraspStatus::kNoPalmContact,
           "a finger touches the object before the palm when the hand leaves it");
    return false;
  }
  if (palm_touch) {
    palm_.translation() += (m_.squeeze + std::max(palm_gap, 0.0)) * a_;
    pressed_ = m_.squeeze;
  }
  return true;
}

// Smallest distance of a palm-rigid link to the object at palm pose `pm`, within `threshold`.
double Trial::palmGap(const Eigen::Isometry3d& pm, double threshold) {
  double gap = kInf;
  for (int l : m_.shaped) {
    const auto u = static_cast<std::size_t>(l);
    if (!m_.hand.links()[u].palm) continue;
    gap = std::min(gap, m_.scene->linkDistance(l, pm * lp_[u], threshold));
    ++st_.queries;
  }
  return gap;
}

// Fingertip grasps: coming from outside along +a the hand stops at the first link contact or
// when the palm comes within the standoff of the object, whichever happens first. The exit pose
// is the first contact; if the palm is closer than the standoff there, back off along -a
// (moving by e along -a opens the gap by at most e, so each step is safe) until the palm is the
// standoff away; a back-off that would make a link penetrate (hooked shapes) is not taken.
void Trial::placeFingertips() {
  const double standoff = m_.standoff;
  if (!(standoff > 0.0)) return;
  const double s0 = st_.retraction;
  double s = s0;
  double gap = palmGap(at(s), standoff + tol_);
  for (int it = 0; it < kMaxStandoffSteps && gap < standoff - 0.5 * tol_; ++it) {
    s += standoff - std::max(gap, 0.0);
    gap = palmGap(at(s), standoff + tol_);
  }
  if (s == s0 || evalAll(at(s), tol_, true) < 0.0) return;
  palm_ = at(s);
  st_.standoff = s - s0;
  st_.retraction = s;
}

// Contacts of one link after the squeeze: every pressed triangle that faces the link, merged
// within kMergeRadius (deepest first), reduced to the contact manifold.
void Trial::linkContacts(int l, std::vector<char>* finger_touch) {
  const auto u = static_cast<std::size_t>(l);
  const CollisionScene& scene = *m_.scene;
  // Only penetrating hits make contacts: lean queries ask for hits within kPenetrating (every
  // triangle GJK/EPA finds penetrating, none that planes prove apart), not within tol_.
  thread_local std::vector<TriangleHit> hits;
  hits.clear();
  scene.linkHits(l, palm_ * lp_[u], m_.lean_queries ? kPenetrating : tol_, &hits);
  ++st_.queries;
  std::stable_sort(hits.begin(), hits.end(), [](const TriangleHit& x, const TriangleHit& y) {
    return x.distance < y.distance || (x.distance == y.distance && x.triangle < y.triangle);
  });
  std::vector<Contact> candidates;  // deepest first
  for (const auto& hh : hits) {
    if (!(hh.distance < 0.0)) break;
    // A triangle the link presses from the side (its separation direction far from the face
    // normal, e.g. a side face under a palm lying on the top face) is no contact.
    if (hh.normal.dot(scene.faceNormal(hh.triangle)) < kMinNormalAgreement) continue;
    bool near = false;
    for (const auto& k : candidates)
      if (withinMergeRadius(k.point, hh.point)) {
        near = true;
        break;
      }
    if (near) continue;
    Contact ct;
    ct.point = hh.point;
    ct.normal = scene.faceNormal(hh.triangle);
    ct.depth = -hh.distance;
    ct.link = l;
    candidates.push_back(ct);
  }
  const HandLink& link = m_.hand.links()[u];
  for (const auto& ct : contactManifold(candidates, m_.opt.max_contacts_per_link)) {
    res_.contacts.push_back(ct);
    if (link.palm) res_.palm_contact = true;
    if (link.finger >= 0) (*finger_touch)[static_cast<std::size_t>(link.finger)] = 1;
  }
}

// With the closing's carried separating axes (a copy: the test leaves them as they are): a pair
// whose gap along its axis exceeds tol_ is answered +inf without GJK, as GJK would answer.
bool Trial::selfPenetrating() const {
  const bool axes = m_.diag.self_collision_axes && pair_axis_.size() == m_.partners.size();
  for (const auto& pr : m_.self_pairs) {
    const auto ua = static_cast<std::size_t>(pr.first), ub = static_cast<std::size_t>(pr.second);
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
    if (axes) {
      const auto& mine = m_.partners[ua];
      const auto k =
          static_cast<std::size_t>(std::find(mine.begin(), mine.end(), pr.second) - mine.begin());
      if (k < mine.size()) axis = pair_axis_[ua][k];
    }
    if (m_.scene->linkLinkDistance(pr.first, palm_ * lp_[ua], pr.second, palm_ * lp_[ub], tol_,
                                   axes ? &axis : nullptr) < -tol_)
      return true;
  }
  return false;
}

void Trial::collectContacts() {
  if (status_only_) {  // judge: the step limit, then self-collision, whatever the contacts
    if (!step_limit_) self_ = m_.opt.check_self_collision && selfPenetrating();
    if (step_limit_ || self_) {
      if (m_.diag.profile) st_.contacts_seconds = lap();
      return;
    }
  }
  std::vector<char> finger_touch(m_.hand.fingerNames().size(), 0);
  for (int l : m_.shaped) linkContacts(l, &finger_touch);
  for (std::size_t f = 0; f < finger_touch.size(); ++f)
    if (finger_touch[f]) res_.fingers_in_contact.push_back(m_.hand.fingerNames()[f]);
  if (!status_only_) self_ = m_.opt.check_self_collision && selfPenetrating();
  if (m_.grasp_mode == GraspMode::kFingertip) st_.palm_gap = palmGap(palm_, kPalmGapRange);
  if (m_.diag.profile) st_.contacts_seconds = lap();
}

void Trial::judge() {
  if (step_limit_)
    finish(GraspStatus::kStepLimit, "closing did not settle within max_closing_steps");
  else if (self_)
    finish(GraspStatus::kSelfCollision, "hand links penetrate each other after closing");
  else if (res_.fingers_in_contact.empty())
    finish(GraspStatus::kNoFingerContact,
           "the fingers closed to their limits without pressing the object");
  else
    finish(GraspStatus::kOk, "");
}

}  // namespace taskmap
