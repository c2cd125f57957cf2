// GraspSimulator: options, the fixed per-simulator data (SimModel) and the trial driver; the
// steps (retraction, autoGrasp closing, squeeze, contacts) are in trial.cpp and
// trial_closing.cpp. Semantics are documented in grasp_simulator.hpp.
#include "taskmap/grasp_sim/grasp_simulator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "sim_model.hpp"
#include "taskmap/core/error.hpp"
#include "trial.hpp"

namespace taskmap {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

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
    throw Error("simulation option contact_tolerance must be in (0, 0.01] metres, got " +
                std::to_string(contact_tolerance));
  if (!(max_retraction >= 0.0 && std::isfinite(max_retraction)))
    throw Error("simulation option max_retraction must be >= 0 metres (0 = automatic), got " +
                std::to_string(max_retraction));
  if (!(squeeze <= 0.01) || std::isnan(squeeze))
    throw Error("simulation option squeeze must be <= 0.01 metres (negative = the hand's), got " +
                std::to_string(squeeze));
  if (max_closing_steps < 10)
    throw Error("simulation option max_closing_steps must be at least 10, got " +
                std::to_string(max_closing_steps));
  if (!(standoff <= 0.5) || std::isnan(standoff))
    throw Error("standoff (--standoff) must be <= 0.5 metres (negative = the hand's), got " +
                std::to_string(standoff));
  if (max_contacts_per_link < 0)
    throw Error("simulation option max_contacts_per_link must be >= 0 (0 = unlimited), got " +
                std::to_string(max_contacts_per_link));
}

double resolveStandoff(const HandModel& hand, const GraspSimOptions& options) {
  options.validate();
  if (options.standoff >= 0.0) return options.standoff;
  if (hand.hasStandoff()) return hand.standoff();
  return std::max(kDefaultStandoffShare * hand.rotationScale(), 4.0 * options.contact_tolerance);
}

struct GraspSimulator::Impl {
  SimModel model;
  Impl(const TriangleMesh& mesh, const HandModel& h, const GraspSimOptions& o,
       const GraspSimDiagnostics& d)
      : model(mesh, h, o, d) {}
};

SimModel::SimModel(const TriangleMesh& mesh, const HandModel& h, const GraspSimOptions& o,
                   const GraspSimDiagnostics& d)
    : hand(h), opt(o), diag(d) {
  opt.validate();
  scene = std::make_unique<CollisionScene>(
      mesh, hand, diag.culled_queries ? CollisionScene::Mode::kAuto : CollisionScene::Mode::kBullet,
      diag.separating_axis_contacts);
  lean_queries = diag.culled_queries;
  squeeze = opt.squeeze >= 0.0 ? opt.squeeze : hand.squeeze();
  const auto& links = hand.links();
  thickness.assign(links.size(), kInf);
  for (std::size_t l = 0; l < links.size(); ++l)
    radius.push_back(scene->linkRadius(static_cast<int>(l)));
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

  // Self-collision pairs: not both palm-rigid, not geometric parent/child, not excluded by the
  // hand's model (an MJCF's <contact><exclude>), apart in preshape.
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
      const auto& excluded = hand.dynamics().excluded_pairs;
      if (std::find(excluded.begin(), excluded.end(), std::array<int, 2>{a, b}) != excluded.end())
        continue;  // shaped is in link order: a < b, as the pairs are stored
      if (scene->linkLinkDistance(a, poses[ua], b, poses[ub], tol) <= tol) continue;
      self_pairs.emplace_back(a, b);
    }
  if (lean_queries && diag.self_pair_proofs) dropPairsProvenApart(this);
  partners.assign(links.size(), {});
  for (const auto& pr : self_pairs) {
    partners[static_cast<std::size_t>(pr.first)].push_back(pr.second);
    partners[static_cast<std::size_t>(pr.second)].push_back(pr.first);
  }
  partner_slot.assign(links.size(), {});
  for (std::size_t u = 0; u < partners.size(); ++u)
    for (int partner : partners[u]) {
      const auto& back = partners[static_cast<std::size_t>(partner)];
      partner_slot[u].push_back(static_cast<int>(
          std::find(back.begin(), back.end(), static_cast<int>(u)) - back.begin()));
    }
  grasp_mode = opt.grasp_mode ? *opt.grasp_mode : hand.graspMode();
  standoff = resolveStandoff(hand, opt);
  group_of.assign(hand.closing().size(), -1);
  if (opt.centre_coupled) findCoupledGroups();
}

// Candidate mechanisms: each sidecar "coupled" group, and every other closing joint alone. A
// candidate centres when the links it moves lie on two or more fingers (a <mimic> jaw pair).
void SimModel::findCoupledGroups() {
  const auto& closing = hand.closing();
  std::vector<std::vector<int>> candidates = hand.coupledClosing();
  std::vector<char> grouped(closing.size(), 0);
  for (const auto& g : candidates)
    for (int c : g) grouped[static_cast<std::size_t>(c)] = 1;
  for (std::size_t c = 0; c < closing.size(); ++c)
    if (!grouped[c]) candidates.push_back({static_cast<int>(c)});
  group_of.assign(closing.size(), -1);
  const auto& links = hand.links();
  for (const auto& g : candidates) {
    std::vector<char> moves(links.size(), 0);
    std::vector<char> finger_seen(hand.fingerNames().size(), 0);
    for (std::size_t l = 0; l < links.size(); ++l)
      for (int j : hand.linkDrivers()[l])
        for (int c : g)
          if (closing[static_cast<std::size_t>(c)].joint == j) moves[l] = 1;
    for (std::size_t l = 0; l < links.size(); ++l)
      if (moves[l] && links[l].finger >= 0)
        finger_seen[static_cast<std::size_t>(links[l].finger)] = 1;
    if (std::count(finger_seen.begin(), finger_seen.end(), 1) < 2) continue;
    for (int c : g) group_of[static_cast<std::size_t>(c)] = static_cast<int>(groups.size());
    groups.push_back(g);
    group_moves.push_back(moves);
  }
}

// The driver: one trial as a sequence of named steps (trial.hpp); a step that ends the trial
// early returns false with the status set.
GraspResult GraspSimulator::simulate(const Pose& initial_palm_pose) const {
  return simulate(initial_palm_pose, FailureDetail::kFull);
}

GraspResult GraspSimulator::simulate(const Pose& initial_palm_pose, FailureDetail detail) const {
  Trial trial(impl_->model, initial_palm_pose, detail == FailureDetail::kStatus);
  if (trial.retract() && trial.placePalm()) {
    trial.close();
    trial.squeeze();
    trial.collectContacts();
    trial.judge();
  }
  return trial.takeResult();
}

GraspSimulator::GraspSimulator(const ObjectModel& object, const HandModel& hand,
                               const GraspSimOptions& options,
                               const GraspSimDiagnostics& diagnostics)
    : impl_(std::make_unique<Impl>(object.mesh(), hand, options, diagnostics)) {}

GraspSimulator::GraspSimulator(const TriangleMesh& mesh, const HandModel& hand,
                               const GraspSimOptions& options,
                               const GraspSimDiagnostics& diagnostics)
    : impl_(std::make_unique<Impl>(mesh, hand, options, diagnostics)) {}

GraspSimulator::~GraspSimulator() = default;

const HandModel& GraspSimulator::hand() const {
  return impl_->model.hand;
}
const GraspSimOptions& GraspSimulator::options() const {
  return impl_->model.opt;
}

const GraspSimDiagnostics& GraspSimulator::diagnostics() const {
  return impl_->model.diag;
}

}  // namespace taskmap
