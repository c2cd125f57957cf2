// GraspSimulator: retraction, autoGrasp closing, squeeze and contact extraction on top of the
// private CollisionScene (Bullet). Semantics are documented in grasp_simulator.hpp.
#include "taskmap/grasp_sim/grasp_simulator.hpp"
#include "taskmap/grasp_sim/contact_manifold.hpp"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <limits>
#include <set>

#include "collision_scene.hpp"
#include "squeeze.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Contacts of one link closer than this are merged (the deepest is kept), metres.
constexpr double kMergeRadius = 1e-3;
/// Deepest penetration the squeeze may cause, in multiples of the squeeze distance.
constexpr double kMaxSqueezeFactor = 2.0;
/// Bisection steps when the squeeze has to be scaled back.
constexpr int kSqueezeBisections = 6;
/// Minimum cosine between a triangle's normal and the separation direction for a contact.
constexpr double kMinNormalAgreement = 0.5;

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

const char* toString(GraspStatus s) {
  switch (s) {
    case GraspStatus::kOk:
      return "ok";
    case GraspStatus::kNotRetractable:
      return "not_retractable";
    case GraspStatus::kNoPalmContact:
      return "no_palm_contact";
    case GraspStatus::kNoFingerContact:
      return "no_finger_contact";
    case GraspStatus::kSelfCollision:
      return "self_collision";
    case GraspStatus::kStepLimit:
      return "step_limit";
  }
  return "unknown";
}

const std::vector<GraspStatus>& allGraspStatuses() {
  static const std::vector<GraspStatus> kAll = {GraspStatus::kOk,
                                                GraspStatus::kNotRetractable,
                                                GraspStatus::kNoPalmContact,
                                                GraspStatus::kNoFingerContact,
                                                GraspStatus::kSelfCollision,
                                                GraspStatus::kStepLimit};
  return kAll;
}

void GraspSimOptions::validate() const {
  if (!(contact_tolerance > 0.0 && contact_tolerance <= 0.01))
    throw Error("GraspSimOptions.contact_tolerance must be in (0, 0.01] metres, got " +
                std::to_string(contact_tolerance));
  if (!(max_retraction >= 0.0 && std::isfinite(max_retraction)))
    throw Error("GraspSimOptions.max_retraction must be >= 0 metres (0 = automatic), got " +
                std::to_string(max_retraction));
  if (!(squeeze <= 0.01) || std::isnan(squeeze))
    throw Error("GraspSimOptions.squeeze must be <= 0.01 metres (negative = the hand's), got " +
                std::to_string(squeeze));
  if (max_closing_steps < 10)
    throw Error("GraspSimOptions.max_closing_steps must be at least 10, got " +
                std::to_string(max_closing_steps));
  if (max_contacts_per_link < 0)
    throw Error("GraspSimOptions.max_contacts_per_link must be >= 0 (0 = unlimited), got " +
                std::to_string(max_contacts_per_link));
}

struct GraspSimulator::Impl {
  HandModel hand;
  GraspSimOptions opt;
  std::unique_ptr<CollisionScene> scene;
  double squeeze = 0.0;
  double retract_step = 0.0;      // coarse retraction step, metres
  std::vector<int> shaped;        // links with collision shapes
  std::vector<double> thickness;  // per link, +inf without shapes
  std::vector<int> closing_of;    // actuated joint -> index in hand.closing(), -1
  std::vector<std::pair<int, int>> self_pairs;
  std::vector<std::vector<int>> partners;  // per link: links of its self-collision pairs

  Impl(const TriangleMesh& mesh, const HandModel& h, const GraspSimOptions& o);
  GraspResult run(const Pose& initial) const;
};

GraspSimulator::Impl::Impl(const TriangleMesh& mesh, const HandModel& h, const GraspSimOptions& o)
    : hand(h), opt(o) {
  opt.validate();
  scene = std::make_unique<CollisionScene>(mesh, hand);
  squeeze = opt.squeeze >= 0.0 ? opt.squeeze : hand.squeeze();
  const auto& links = hand.links();
  thickness.assign(links.size(), kInf);
  double thinnest = kInf;
  for (std::size_t l = 0; l < links.size(); ++l) {
    if (links[l].shapes.empty()) continue;
    shaped.push_back(static_cast<int>(l));
    for (const auto& s : links[l].shapes) thickness[l] = std::min(thickness[l], s.thickness());
    thinnest = std::min(thinnest, thickness[l]);
  }
  const double tol = opt.contact_tolerance;
  retract_step = std::clamp(0.5 * thinnest, 4.0 * tol, 0.02);
  closing_of.assign(hand.jointNames().size(), -1);
  for (std::size_t c = 0; c < hand.closing().size(); ++c)
    closing_of[static_cast<std::size_t>(hand.closing()[c].joint)] = static_cast<int>(c);

  // Self-collision pairs: not both palm-rigid, not geometric parent/child, apart in preshape.
  auto geometric_parent = [&](int l) {
    int cur = l;
    while (true) {
      const int pj = links[static_cast<std::size_t>(cur)].parent_joint;
      if (pj < 0) return -1;
      cur = hand.joints()[static_cast<std::size_t>(pj)].parent_link;
      if (!links[static_cast<std::size_t>(cur)].shapes.empty()) return cur;
    }
  };
  const auto poses = hand.linkPoses(hand.preshape());
  for (std::size_t i = 0; i < shaped.size(); ++i)
    for (std::size_t j = i + 1; j < shaped.size(); ++j) {
      const int a = shaped[i], b = shaped[j];
      const auto ua = static_cast<std::size_t>(a), ub = static_cast<std::size_t>(b);
      if (links[ua].palm && links[ub].palm) continue;
      if (geometric_parent(a) == b || geometric_parent(b) == a) continue;
      if (scene->linkLinkDistance(a, poses[ua], b, poses[ub], tol) <= tol) continue;
      self_pairs.emplace_back(a, b);
    }
  partners.assign(links.size(), {});
  for (const auto& pr : self_pairs) {
    partners[static_cast<std::size_t>(pr.first)].push_back(pr.second);
    partners[static_cast<std::size_t>(pr.second)].push_back(pr.first);
  }
}

GraspResult GraspSimulator::Impl::run(const Pose& initial) const {
  GraspResult res;
  GraspStats& st = res.stats;
  const double tol = opt.contact_tolerance;
  const auto& links = hand.links();
  const auto& closing = hand.closing();
  const std::size_t nl = links.size();
  const bool prof = opt.profile;
  auto t0 = prof ? Clock::now() : Clock::time_point();

  Eigen::Isometry3d palm = initial.toIsometry();
  const Eigen::Vector3d p0 = palm.translation();
  const Eigen::Vector3d a = (palm.linear() * hand.approachAxis()).normalized();
  Eigen::VectorXd q = hand.preshape();
  std::vector<Eigen::Isometry3d> lp = hand.linkPoses(q);
  std::vector<double> dist(nl, kInf);

  // Signed distance of every shaped link at palm pose `pm` (threshold-limited); -inf when a
  // link lies wholly inside the object (checked only when `inside_check`). With `inside_check`
  // the evaluation stops at the first penetrating link, trying the last one found first
  // (`dist` is then complete only for collision-free poses).
  std::size_t first = 0;
  auto eval_all = [&](const Eigen::Isometry3d& pm, double threshold, bool inside_check) {
    double mn = kInf;
    for (std::size_t k = 0; k < shaped.size(); ++k) {
      const std::size_t idx = (first + k) % shaped.size();
      const int l = shaped[idx];
      const auto u = static_cast<std::size_t>(l);
      const Eigen::Isometry3d t = pm * lp[u];
      double d = scene->linkDistance(l, t, threshold);
      ++st.queries;
      if (inside_check && d == kInf && scene->linkInside(l, t)) d = -kInf;
      dist[u] = d;
      mn = std::min(mn, d);
      if (inside_check && d < 0.0) {
        first = idx;
        break;
      }
    }
    return mn;
  };
  auto at = [&](double s) {
    Eigen::Isometry3d pm = palm;
    pm.translation() = p0 - s * a;
    return pm;
  };
  auto finish = [&](GraspStatus status, const std::string& msg) {
    res.status = status;
    res.message = msg;
    res.pose = Pose::fromIsometry(palm);
    res.joints = q;
    return res;
  };

  // ---- Retraction ----
  const double s_max = opt.max_retraction > 0.0 ? opt.max_retraction
                                                : (p0 - scene->objectCentre()).norm() +
                                                      scene->objectRadius() + hand.reach() + 0.01;
  double s = 0.0;
  double m = eval_all(at(0.0), tol, true);
  if (m < 0.0) {
    double lo = 0.0, hi = 0.0;
    while (true) {
      const double step = std::max(retract_step, std::isfinite(m) ? -m : 0.0);
      hi = std::min(lo + step, s_max);
      m = eval_all(at(hi), tol, true);
      if (m >= 0.0) break;
      lo = hi;
      if (hi >= s_max) {
        palm = at(s_max);
        st.retraction = s_max;
        return finish(GraspStatus::kNotRetractable,
                      "the hand still penetrates the object after retracting " +
                          std::to_string(s_max) + " m along its approach axis");
      }
    }
    // Bisection: lo penetrates, hi is free; stop when the free side touches within tol.
    std::vector<double> dist_hi = dist;
    while (m > tol && hi - lo > 1e-9) {
      const double mid = 0.5 * (lo + hi);
      const double mm = eval_all(at(mid), tol, true);
      if (mm < 0.0) {
        lo = mid;
      } else {
        hi = mid;
        m = mm;
        dist_hi = dist;
      }
    }
    dist = dist_hi;
    s = hi;
  } else if (m > tol) {
    // Free at the start: advance along +a (conservative advancement) until touching.
    const double far = std::max(4.0 * retract_step, 0.02);
    while (true) {
      m = eval_all(at(s), far, false);
      if (m <= tol) break;
      const double step = std::isfinite(m) ? m - 0.25 * tol : far;
      s -= step;
      if (-s > s_max) {
        palm = at(s);
        st.retraction = s;
        return finish(GraspStatus::kNoPalmContact,
                      "the hand touches nothing when advanced along its approach axis");
      }
    }
  }
  palm = at(s);
  st.retraction = s;
  bool palm_touch = false;
  double palm_gap = kInf;
  for (int l : shaped)
    if (links[static_cast<std::size_t>(l)].palm && dist[static_cast<std::size_t>(l)] <= tol) {
      palm_touch = true;
      palm_gap = std::min(palm_gap, dist[static_cast<std::size_t>(l)]);
    }
  if (prof) {
    st.retract_seconds = secondsSince(t0);
    t0 = Clock::now();
  }
  if (!palm_touch && opt.require_palm_contact)
    return finish(GraspStatus::kNoPalmContact,
                  "a finger touches the object before the palm when the hand leaves it");
  if (palm_touch) palm.translation() += (squeeze + std::max(palm_gap, 0.0)) * a;  // press the palm

  // ---- Closing (autoGrasp) ----
  const std::size_t nc = closing.size();
  std::vector<char> active(nc, 0);
  std::vector<int> stop_link(nc, -1);
  std::vector<double> dir(nc, 0.0);
  for (std::size_t c = 0; c < nc; ++c) {
    const double diff = closing[c].target - q[closing[c].joint];
    dir[c] = diff > 0 ? 1.0 : -1.0;
    active[c] = std::abs(diff) > 1e-12;
  }
  const auto& drivers = hand.linkDrivers();
  const auto& levers = hand.jointLevers();
  auto moving = [&](int l) {
    for (int j : drivers[static_cast<std::size_t>(l)]) {
      const int c = closing_of[static_cast<std::size_t>(j)];
      if (c >= 0 && active[static_cast<std::size_t>(c)]) return true;
    }
    return false;
  };
  auto advance = [&](const Eigen::VectorXd& from, double dt) {
    Eigen::VectorXd out = from;
    for (std::size_t c = 0; c < nc; ++c) {
      if (!active[c]) continue;
      const int j = closing[c].joint;
      const double v = from[j] + dir[c] * closing[c].speed * dt;
      out[j] = dir[c] > 0 ? std::min(v, closing[c].target) : std::max(v, closing[c].target);
    }
    return out;
  };
  std::vector<int> mov;
  // Distances of the moving links at joint values qq, to the object and (self-contact stops
  // a link like an object contact) to the hand links it may collide with; returns the minimum.
  std::vector<Eigen::Isometry3d> world(nl);
  auto eval_moving = [&](const Eigen::VectorXd& qq) {
    lp = hand.linkPoses(qq);
    for (int l : shaped)
      world[static_cast<std::size_t>(l)] = palm * lp[static_cast<std::size_t>(l)];
    double mn = kInf;
    for (int l : mov) {
      const auto u = static_cast<std::size_t>(l);
      const Eigen::Isometry3d& tl = world[u];
      double d = scene->linkDistance(l, tl, tol);
      ++st.queries;
      if (opt.check_self_collision)
        for (int o : partners[u])
          d = std::min(d,
                       scene->linkLinkDistance(l, tl, o, world[static_cast<std::size_t>(o)], tol));
      dist[u] = d;
      mn = std::min(mn, d);
    }
    ++st.closing_steps;
    return mn;
  };
  auto stop_touching = [&](const std::vector<int>& touching) {
    for (int l : touching)
      for (int j : drivers[static_cast<std::size_t>(l)]) {
        const int c = closing_of[static_cast<std::size_t>(j)];
        if (c >= 0 && active[static_cast<std::size_t>(c)]) {
          active[static_cast<std::size_t>(c)] = 0;
          stop_link[static_cast<std::size_t>(c)] = l;
        }
      }
  };
  auto refresh_moving = [&]() {
    mov.clear();
    for (int l : shaped)
      if (moving(l)) mov.push_back(l);
  };

  refresh_moving();
  eval_moving(q);
  {
    std::vector<int> touching;
    for (int l : mov)
      if (dist[static_cast<std::size_t>(l)] <= tol) touching.push_back(l);
    stop_touching(touching);
  }
  bool step_limit = false;
  while (true) {
    refresh_moving();
    if (mov.empty()) break;
    if (st.closing_steps >= opt.max_closing_steps) {
      step_limit = true;
      break;
    }
    // Step bound per moving link: no point of it moves more than half its thickness. `rate`
    // bounds the speed (metres per unit time) of every point of every moving link.
    double rate = 0.0, dt_lim = kInf, dt_step = kInf;
    for (std::size_t c = 0; c < nc; ++c) {
      if (!active[c]) continue;
      const int j = closing[c].joint;
      dt_lim = std::min(dt_lim, std::abs(closing[c].target - q[j]) / closing[c].speed);
    }
    for (int l : mov) {
      double link_rate = 0.0;
      for (int j : drivers[static_cast<std::size_t>(l)]) {
        const int c = closing_of[static_cast<std::size_t>(j)];
        if (c >= 0 && active[static_cast<std::size_t>(c)])
          link_rate +=
              closing[static_cast<std::size_t>(c)].speed * levers[static_cast<std::size_t>(j)];
      }
      rate = std::max(rate, link_rate);
      const double h = std::clamp(0.5 * thickness[static_cast<std::size_t>(l)], 2.0 * tol, 0.02);
      dt_step = std::min(dt_step, h / std::max(link_rate, 1e-12));
    }
    const double dt = std::min(dt_step, dt_lim);
    const Eigen::VectorXd q1 = advance(q, dt);
    double m1 = eval_moving(q1);
    std::vector<int> touching;
    if (m1 < 0.0) {
      // Bisection on the step: lo is free (moving links > tol apart at its start), hi
      // penetrates. Ends when a free state touches, or when the Lipschitz bound rate * (hi - lo)
      // <= tol proves that the links penetrating at hi are within tol of contact at lo.
      double lo = 0.0, hi = dt;
      std::vector<double> dist_lo(nl, kInf), dist_hi = dist;
      bool touching_lo = false;
      while ((hi - lo) * rate > tol && st.closing_steps < opt.max_closing_steps) {
        const double mid = 0.5 * (lo + hi);
        const double mm = eval_moving(advance(q, mid));
        if (mm < 0.0) {
          hi = mid;
          dist_hi = dist;
        } else {
          lo = mid;
          dist_lo = dist;
          if (mm <= tol) {
            touching_lo = true;
            break;
          }
        }
      }
      q = advance(q, lo);
      for (int l : mov) {
        const auto u = static_cast<std::size_t>(l);
        if (dist_lo[u] <= tol || (!touching_lo && dist_hi[u] < 0.0)) touching.push_back(l);
      }
      lp = hand.linkPoses(q);
    } else {
      q = q1;
      for (int l : mov)
        if (dist[static_cast<std::size_t>(l)] <= tol) touching.push_back(l);
    }
    stop_touching(touching);
    for (std::size_t c = 0; c < nc; ++c)
      if (active[c] && std::abs(q[closing[c].joint] - closing[c].target) <= 1e-12) active[c] = 0;
  }
  lp = hand.linkPoses(q);

  // ---- Squeeze: press each contact-stopped joint's contact point `squeeze` deeper ----
  if (squeeze > 0.0) {
    std::vector<SqueezeContact> pressing;
    for (std::size_t c = 0; c < nc; ++c) {
      const int l = stop_link[c];
      if (l < 0) continue;
      std::vector<TriangleHit> hits;
      scene->linkHits(l, palm * lp[static_cast<std::size_t>(l)], tol, &hits);
      ++st.queries;
      // The closest hit on a triangle that faces the link (see kMinNormalAgreement); none
      // when the link was stopped by the hand itself.
      const TriangleHit* best = nullptr;
      for (const auto& hh : hits) {
        if (hh.normal.dot(scene->faceNormal(hh.triangle)) < kMinNormalAgreement) continue;
        if (!best || hh.distance < best->distance) best = &hh;
      }
      if (!best) continue;
      SqueezeContact sc;
      sc.joint = closing[c].joint;
      sc.link = l;
      sc.point = best->point;
      sc.normal = scene->faceNormal(best->triangle);
      sc.gap = best->distance;
      sc.dir = dir[c];
      sc.target = closing[c].target;
      pressing.push_back(sc);
    }
    const Eigen::VectorXd q_contact = q;
    applySqueeze(hand, palm, lp, pressing, squeeze, &q);
    // The squeeze is first order and moves whole chains: a link farther out on a squeezed chain
    // may press much deeper than its own contact. Scale the squeeze back (bisection) until no
    // link moved by it presses deeper than kMaxSqueezeFactor * squeeze + tolerance.
    std::vector<int> squeezed;
    for (int l : shaped)
      for (int j : drivers[static_cast<std::size_t>(l)])
        if (q[j] != q_contact[j]) {
          squeezed.push_back(l);
          break;
        }
    const double limit = kMaxSqueezeFactor * squeeze + tol;
    auto deepest = [&](const Eigen::VectorXd& qq) {
      const auto poses = hand.linkPoses(qq);
      double deep = 0.0;
      for (int l : squeezed) {
        std::vector<TriangleHit> hits;
        scene->linkHits(l, palm * poses[static_cast<std::size_t>(l)], tol, &hits);
        ++st.queries;
        for (const auto& hh : hits)
          if (hh.normal.dot(scene->faceNormal(hh.triangle)) >= kMinNormalAgreement)
            deep = std::max(deep, -hh.distance);
      }
      return deep;
    };
    if (!squeezed.empty() && deepest(q) > limit) {
      const Eigen::VectorXd full = q - q_contact;
      double lo = 0.0, hi = 1.0;
      for (int it = 0; it < kSqueezeBisections; ++it) {
        const double mid = 0.5 * (lo + hi);
        (deepest(q_contact + mid * full) > limit ? hi : lo) = mid;
      }
      q = q_contact + lo * full;
    }
    lp = hand.linkPoses(q);
  }
  if (prof) {
    st.close_seconds = secondsSince(t0);
    t0 = Clock::now();
  }

  // ---- Contacts ----
  std::vector<char> finger_touch(hand.fingerNames().size(), 0);
  for (int l : shaped) {
    const auto u = static_cast<std::size_t>(l);
    std::vector<TriangleHit> hits;
    scene->linkHits(l, palm * lp[u], tol, &hits);
    ++st.queries;
    std::stable_sort(hits.begin(), hits.end(), [](const TriangleHit& x, const TriangleHit& y) {
      return x.distance < y.distance || (x.distance == y.distance && x.triangle < y.triangle);
    });
    std::vector<Contact> candidates;  // deepest first
    for (const auto& hh : hits) {
      if (!(hh.distance < 0.0)) break;
      // A triangle the link presses from the side (its separation direction far from the
      // face normal, e.g. a side face under a palm lying on the top face) is no contact.
      if (hh.normal.dot(scene->faceNormal(hh.triangle)) < kMinNormalAgreement) continue;
      bool near = false;
      for (const auto& k : candidates)
        if ((k.point - hh.point).norm() < kMergeRadius) near = true;
      if (near) continue;
      Contact ct;
      ct.point = hh.point;
      ct.normal = scene->faceNormal(hh.triangle);
      ct.depth = -hh.distance;
      ct.link = l;
      candidates.push_back(ct);
    }
    for (const auto& ct : contactManifold(candidates, opt.max_contacts_per_link)) {
      res.contacts.push_back(ct);
      if (links[u].palm) res.palm_contact = true;
      if (links[u].finger >= 0) finger_touch[static_cast<std::size_t>(links[u].finger)] = 1;
    }
  }
  for (std::size_t f = 0; f < finger_touch.size(); ++f)
    if (finger_touch[f]) res.fingers_in_contact.push_back(hand.fingerNames()[f]);

  bool self = false;
  if (opt.check_self_collision)
    for (const auto& pr : self_pairs) {
      const auto ua = static_cast<std::size_t>(pr.first), ub = static_cast<std::size_t>(pr.second);
      if (scene->linkLinkDistance(pr.first, palm * lp[ua], pr.second, palm * lp[ub], tol) < -tol) {
        self = true;
        break;
      }
    }
  if (prof) st.contacts_seconds = secondsSince(t0);

  if (step_limit)
    return finish(GraspStatus::kStepLimit, "closing did not settle within max_closing_steps");
  if (self)
    return finish(GraspStatus::kSelfCollision, "hand links penetrate each other after closing");
  if (res.fingers_in_contact.empty())
    return finish(GraspStatus::kNoFingerContact,
                  "the fingers closed to their limits without pressing the object");
  return finish(GraspStatus::kOk, "");
}

GraspSimulator::GraspSimulator(const ObjectModel& object, const HandModel& hand,
                               const GraspSimOptions& options)
    : impl_(std::make_unique<Impl>(object.mesh(), hand, options)) {}

GraspSimulator::GraspSimulator(const TriangleMesh& mesh, const HandModel& hand,
                               const GraspSimOptions& options)
    : impl_(std::make_unique<Impl>(mesh, hand, options)) {}

GraspSimulator::~GraspSimulator() = default;

GraspResult GraspSimulator::simulate(const Pose& initial_palm_pose) const {
  return impl_->run(initial_palm_pose);
}

const HandModel& GraspSimulator::hand() const {
  return impl_->hand;
}
const GraspSimOptions& GraspSimulator::options() const {
  return impl_->opt;
}

}  // namespace taskmap
