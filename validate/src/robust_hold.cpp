// The robust hold test (docs/VALIDATION.md, "The robust label"): the hold test under the
// variants of a grasp a robot and a mesh bring. Steps: the nominal variant (protocol label, then
// the margin), then every other variant on its model, stopping at the first failure unless all
// are asked for.
#include "taskmap/validate/robust_hold.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"

namespace taskmap {

std::string HoldVariant::name() const {
  static const char* const kAxes = "xyz";
  const std::string sign = amount < 0.0 ? "-" : "+";
  switch (kind) {
    case Kind::kNominal:
      return "nominal";
    case Kind::kPalmShift:
      return "shift" + sign + kAxes[axis];
    case Kind::kPalmTurn:
      return "turn" + sign + kAxes[axis];
    case Kind::kFriction:
      return "friction";
    case Kind::kDecomposition:
      return "decomposition";
  }
  return "?";
}

Pose HoldVariant::apply(const Pose& palm) const {
  Eigen::Isometry3d delta = Eigen::Isometry3d::Identity();
  if (kind == Kind::kPalmShift) delta.translation()[axis] = amount;
  if (kind == Kind::kPalmTurn)
    delta.linear() = Eigen::AngleAxisd(amount, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
  if (kind != Kind::kPalmShift && kind != Kind::kPalmTurn) return palm;
  return Pose::fromIsometry(palm.toIsometry() * delta);
}

void RobustHoldOptions::validate() const {
  hold.validate();
  if (!(palm_shift >= 0.0 && palm_shift < 0.05))
    throw Error("robust hold option palm_shift must be in [0, 0.05) metres (0: no shift variants)");
  if (!(palm_turn >= 0.0 && palm_turn < 0.5))
    throw Error("robust hold option palm_turn must be in [0, 0.5) radians (0: no turn variants)");
  if (!(friction >= 0.0 && std::isfinite(friction)))
    throw Error("robust hold option friction must be >= 0 (0: no friction variant)");
  if (decomposition_faces != 0 && (decomposition_faces < 50 || decomposition_faces > 5000))
    throw Error("robust hold option decomposition_faces must be 0 (off) or in [50, 5000]");
  if (decomposition_pieces < 1 || decomposition_pieces > 64)
    throw Error("robust hold option decomposition_pieces must be in [1, 64]");
  if (!(margin_translation > 0.0) || !(margin_rotation > 0.0))
    throw Error("robust hold options margin_translation and margin_rotation must be > 0");
}

double RobustHoldResult::share() const {
  return tested > 0 ? static_cast<double>(held) / tested : 0.0;
}

namespace {}  // namespace

// Test order: the variants that failed most often where the nominal one held first (measured
// on 164 such grasps of six pairs, docs/VALIDATION.md "The robust label"), so that a build stops
// early: the turns about the palm's y and x axes, friction, the other turns, the shifts along
// the approach axis, the other shifts, the second decomposition.
std::vector<HoldVariant> robustVariants(const RobustHoldOptions& o, bool decomposition) {
  using K = HoldVariant::Kind;
  std::vector<HoldVariant> v{{K::kNominal, 0, 0.0}};
  const double t = o.palm_turn, m = o.palm_shift;
  const auto turn = [&](int axis, double sign) {
    if (t > 0.0) v.push_back({K::kPalmTurn, axis, sign * t});
  };
  const auto shift = [&](int axis, double sign) {
    if (m > 0.0) v.push_back({K::kPalmShift, axis, sign * m});
  };
  turn(1, 1.0), turn(1, -1.0), turn(0, 1.0);
  if (o.friction > 0.0) v.push_back({K::kFriction, 0, o.friction});
  turn(0, -1.0), turn(2, -1.0), turn(2, 1.0);
  shift(2, 1.0), shift(2, -1.0), shift(1, -1.0), shift(1, 1.0), shift(0, -1.0), shift(0, 1.0);
  if (decomposition) v.push_back({K::kDecomposition, 0, 0.0});
  return v;
}

namespace {

bool withinMargin(const HoldResult& r, const HoldTestOptions& margin) {
  return r.holds && r.push_translation < margin.margin_translation &&
         r.push_rotation < margin.margin_rotation;
}

}  // namespace

struct RobustHoldTester::Impl {
  RobustHoldOptions options;
  HoldTester protocol;  // the protocol without the margin (nominal label)
  HoldTester margin;    // the protocol's model with the margin (nominal, palm variants)
  std::unique_ptr<HoldTester> friction, decomposition;
  std::vector<HoldVariant> variants;

  static HoldTestOptions withMargin(const RobustHoldOptions& o) {
    HoldTestOptions h = o.hold;
    h.margin_translation = o.margin_translation;
    h.margin_rotation = o.margin_rotation;
    return h;
  }
  static HoldTestOptions withoutMargin(const RobustHoldOptions& o) {
    HoldTestOptions h = o.hold;
    h.margin_translation = h.margin_rotation = 0.0;
    return h;
  }

  Impl(const HandModel& hand, const ObjectModel& object, const RobustHoldOptions& o)
      : options(o), protocol(hand, object, withoutMargin(o)), margin(hand, object, withMargin(o)) {
    if (o.friction > 0.0) {
      HoldTestOptions h = withMargin(o);
      h.sliding_friction = o.friction;
      friction = std::make_unique<HoldTester>(hand, object, h);
    }
    if (o.decomposition_faces > 0) {
      HoldTestOptions h = withMargin(o);
      h.object_max_faces = o.decomposition_faces;
      h.object_max_pieces = o.decomposition_pieces;
      decomposition = std::make_unique<HoldTester>(hand, object, h);
      if (decomposition->mjcf() == margin.mjcf()) decomposition.reset();  // the same pieces
    }
    variants = robustVariants(o, decomposition != nullptr);
  }

  const HoldTester& testerOf(const HoldVariant& v) const {
    if (v.kind == HoldVariant::Kind::kFriction) return *friction;
    if (v.kind == HoldVariant::Kind::kDecomposition) return *decomposition;
    return margin;
  }
};

RobustHoldTester::RobustHoldTester(const HandModel& hand, const ObjectModel& object,
                                   const RobustHoldOptions& options) {
  options.validate();
  impl_ = std::make_unique<Impl>(hand, object, options);
}

RobustHoldTester::~RobustHoldTester() = default;
RobustHoldTester::RobustHoldTester(RobustHoldTester&&) noexcept = default;
RobustHoldTester& RobustHoldTester::operator=(RobustHoldTester&&) noexcept = default;

const std::vector<HoldVariant>& RobustHoldTester::variants() const {
  return impl_->variants;
}
const HoldTester& RobustHoldTester::nominal() const {
  return impl_->protocol;
}
const RobustHoldOptions& RobustHoldTester::options() const {
  return impl_->options;
}

RobustHoldResult RobustHoldTester::test(const Pose& palm, const Eigen::VectorXd& joints) const {
  const Impl& s = *impl_;
  RobustHoldResult r;
  r.variant_held.assign(s.variants.size(), 255);
  for (std::size_t k = 0; k < s.variants.size(); ++k) {
    const HoldVariant& v = s.variants[k];
    const HoldTester& tester = s.testerOf(v);
    const HoldResult h = tester.test(v.apply(palm), joints);
    r.steps += h.steps;
    if (k == 0) {
      r.nominal = h;
      if (!h.holds && h.margin_exceeded && s.options.protocol_label) {
        r.nominal = s.protocol.test(palm, joints);
        r.steps += r.nominal.steps;
      }
    }
    const bool held = withinMargin(h, tester.options());
    r.variant_held[k] = held ? 1 : 0;
    ++r.tested;
    r.held += held ? 1 : 0;
    r.push_translation = std::max(r.push_translation, h.push_translation);
    r.push_rotation = std::max(r.push_rotation, h.push_rotation);
    if (!held && !s.options.all_variants) break;
  }
  r.robust = r.held == static_cast<int>(s.variants.size());
  return r;
}

std::string robustParamsJson(const RobustHoldOptions& o, const std::vector<HoldVariant>& variants) {
  nlohmann::ordered_json j;
  nlohmann::ordered_json names = nlohmann::ordered_json::array();
  for (const HoldVariant& v : variants) names.push_back(v.name());
  j["variants"] = names;
  j["palm_shift"] = o.palm_shift;
  j["palm_turn"] = o.palm_turn;
  j["friction"] = o.friction;
  j["decomposition_faces"] = o.decomposition_faces;
  j["decomposition_pieces"] = o.decomposition_pieces;
  j["margin_translation"] = o.margin_translation;
  j["margin_rotation"] = o.margin_rotation;
  return j.dump();
}

}  // namespace taskmap
