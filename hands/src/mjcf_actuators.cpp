// MJCF actuators and fixed tendons (mjcf_reader.hpp): a fixed tendon driven by one actuator
// couples its joints (the first is the driver, each other joint k mimics it with multiplier
// c_k / c_1: the smallest joint motion that changes the tendon's length), and each actuator's
// position servo becomes the stated dynamics of the joint it drives, in that joint's units.
#include <algorithm>
#include <cmath>

#include "mjcf_reader.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap::detail {
namespace {

/// Actuator elements; in a default class they share one actuator default (MuJoCo).
const std::vector<const char*> kActuators = {"general",  "motor",       "position",
                                             "velocity", "intvelocity", "damper",
                                             "cylinder", "muscle",      "adhesion"};

}  // namespace

void MjcfReader::readTendons() {
  for (const TiXmlElement* section : doc_.children(doc_.root(), "tendon"))
    for (const TiXmlElement* t : doc_.children(section)) {
      const std::string tag = t->Value();
      const char* name = t->Attribute("name");
      if (tag == "spatial") {
        if (name) spatial_tendons_.insert(name);
        continue;
      }
      if (tag != "fixed") doc_.fail(t, "<" + tag + "> is not a tendon");
      std::vector<TendonJoint> joints;
      for (const TiXmlElement* j : doc_.children(t, "joint")) {
        const int index = jointNamed(j, "joint");
        double coef = 1.0;
        if (const char* c = j->Attribute("coef")) coef = mjcfNumbers(doc_, {c, j}, "coef", 1, 1)[0];
        if (coef == 0.0) doc_.fail(j, "coef must not be zero");
        for (const TendonJoint& seen : joints)
          if (seen.joint == index) doc_.fail(j, "the tendon lists this joint twice");
        joints.push_back({index, coef});
      }
      if (joints.empty()) doc_.fail(t, "a fixed tendon needs at least one <joint>");
      if (name) fixed_tendons_[name] = std::move(joints);
    }
}

void MjcfReader::readActuators() {
  for (const TiXmlElement* section : doc_.children(doc_.root(), "actuator"))
    for (const TiXmlElement* a : doc_.children(section)) addActuator(a);
}

void MjcfReader::addActuator(const TiXmlElement* a) {
  const std::string tag = a->Value();
  if (tag == "plugin") {
    out_.warnings.push_back(doc_.where(a) + ": plugin actuator ignored");
    return;
  }
  if (std::none_of(kActuators.begin(), kActuators.end(), [&](const char* k) { return tag == k; }))
    doc_.fail(a, "<" + tag + "> is not an actuator");
  const int cls = defaults_.classOf(a, defaults_.main());
  double gear = 1.0;
  if (auto g = defaults_.find(a, kActuators, cls, "gear"))
    gear = mjcfNumbers(doc_, *g, "gear", 1, 6)[0];
  if (gear == 0.0) doc_.fail(a, "gear must not be zero");
  int joint = -1;
  if (a->Attribute("joint") || a->Attribute("jointinparent")) {
    joint = jointNamed(a, a->Attribute("joint") ? "joint" : "jointinparent");
    if (followers_.count(joint))
      doc_.fail(a, "drives joint '" + out_.tree.joints[static_cast<std::size_t>(joint)].name +
                       "', which a fixed tendon already couples to its driver");
    if (out_.tree.joints[static_cast<std::size_t>(joint)].mimic) {
      out_.warnings.push_back(doc_.where(a) +
                              ": drives a joint coupled by an <equality>; taskmap drives the "
                              "coupling's driver, so this actuator's servo is not used");
      return;
    }
  } else if (const char* t = a->Attribute("tendon")) {
    if (spatial_tendons_.count(t)) {
      out_.warnings.push_back(doc_.where(a) + ": drives spatial tendon '" + t +
                              "', which taskmap does not model; its joints stay independent");
      return;
    }
    double s = 1.0;
    joint = coupleTendon(a, t, &s);
    gear *= s;
  } else {
    out_.warnings.push_back(doc_.where(a) +
                            ": drives a site or a body, not a joint or a fixed tendon; ignored");
    return;
  }
  auto& slot = out_.dynamics.actuators[static_cast<std::size_t>(joint)];
  if (slot) {
    out_.warnings.push_back(doc_.where(a) + ": joint '" +
                            out_.tree.joints[static_cast<std::size_t>(joint)].name +
                            "' already has an actuator; this one is not used");
    return;
  }
  slot = servoOf(a, cls, gear, joint);
  if (!slot->unused.empty())
    out_.warnings.push_back(doc_.where(a) + ": " + slot->unused +
                            "; the validator drives the joint with its protocol's servo");
}

int MjcfReader::coupleTendon(const TiXmlElement* a, const std::string& tendon, double* gear) {
  const auto it = fixed_tendons_.find(tendon);
  if (it == fixed_tendons_.end())
    doc_.fail(a, "names tendon '" + tendon + "', which no <tendon><fixed> defines");
  const std::vector<TendonJoint>& js = it->second;
  const TendonJoint& driver = js[0];
  double squares = 0.0;
  for (const TendonJoint& j : js) squares += j.coef * j.coef;
  *gear = squares / driver.coef;  // the tendon's length per unit of the driver's value
  if (!coupled_tendons_.insert(tendon).second) return driver.joint;
  auto& joints = out_.tree.joints;
  const auto name = [&](int j) { return joints[static_cast<std::size_t>(j)].name; };
  for (std::size_t k = 0; k < js.size(); ++k) {
    const int j = js[k].joint;
    if (joints[static_cast<std::size_t>(j)].mimic || followers_.count(j))
      doc_.fail(a, "tendon '" + tendon + "' couples joint '" + name(j) +
                       "', which is already coupled: taskmap models a fixed tendon under one "
                       "actuator as mimic joints of its first joint, each joint coupled once");
    if (k > 0 && out_.dynamics.actuators[static_cast<std::size_t>(j)])
      doc_.fail(a, "tendon '" + tendon + "' couples joint '" + name(j) +
                       "', which has its own actuator: the coupling is not a mimic");
  }
  for (std::size_t k = 1; k < js.size(); ++k) {
    joints[static_cast<std::size_t>(js[k].joint)].mimic =
        UrdfMimic{name(driver.joint), js[k].coef / driver.coef, 0.0};
    followers_.insert(js[k].joint);
  }
  return driver.joint;
}

ActuatorDynamics MjcfReader::servoOf(const TiXmlElement* a, int cls, double gear, int joint) const {
  ActuatorDynamics s;
  const std::string tag = a->Value();
  if (const char* n = a->Attribute("name")) s.name = n;
  auto one = [&](const std::vector<const char*>& tags, const char* key) -> std::optional<double> {
    if (auto v = defaults_.find(a, tags, cls, key)) return mjcfNumbers(doc_, *v, key, 1, 1)[0];
    return std::nullopt;
  };
  if (tag == "position") {
    s.kp = one({"position"}, "kp");
    s.kv = one({"position"}, "kv");
    if (defaults_.find(a, {"position"}, cls, "dampratio") ||
        defaults_.find(a, {"position"}, cls, "timeconst"))
      s.unused = "dampratio and timeconst are not read (give kv)";
  } else if (tag == "general") {
    auto text = [&](const char* key, const char* fallback) {
      auto v = defaults_.find(a, kActuators, cls, key);
      return v ? v->text : std::string(fallback);
    };
    const bool affine = text("biastype", "none") == "affine" &&
                        text("gaintype", "fixed") == "fixed" && text("dyntype", "none") == "none";
    std::vector<double> gain{1}, bias{0, 0, 0};
    if (auto g = defaults_.find(a, kActuators, cls, "gainprm"))
      gain = mjcfNumbers(doc_, *g, "gainprm", 1, 10);
    if (auto b = defaults_.find(a, kActuators, cls, "biasprm"))
      bias = mjcfNumbers(doc_, *b, "biasprm", 1, 10);
    bias.resize(std::max<std::size_t>(bias.size(), 3), 0.0);
    if (affine && bias[0] == 0.0 && bias[1] == -gain[0] && gain[0] > 0.0) {
      s.kp = gain[0];
      s.kv = -bias[2];
    } else {
      s.unused = "a <general> actuator that is not a position servo";
    }
  } else {
    s.unused = "a <" + tag + "> actuator, not a position servo";
  }
  const double g2 = gear * gear;
  if (s.kp) *s.kp *= g2;
  if (s.kv) *s.kv *= g2;
  auto range = [&](const char* key,
                   const char* limited_key) -> std::optional<std::array<double, 2>> {
    const auto r = defaults_.find(a, kActuators, cls, key);
    const auto l = defaults_.find(a, kActuators, cls, limited_key);
    const int limited = l ? mjcfBool(doc_, *l, limited_key, true) : -1;
    if (limited == 0 || !r || (limited < 0 && !compiler_.autolimits)) return std::nullopt;
    const auto v = mjcfNumbers(doc_, *r, key, 2, 2);
    if (!(v[0] <= v[1])) doc_.fail(r->at, std::string(key) + " lower must not exceed upper");
    return std::array<double, 2>{v[0], v[1]};
  };
  if (auto c = range("ctrlrange", "ctrllimited")) {  // lengths L = gear q: targets in q
    const double lo = (*c)[0] / gear, hi = (*c)[1] / gear;
    s.ctrlrange = std::array<double, 2>{std::min(lo, hi), std::max(lo, hi)};
  }
  if (auto ir = one({"position"}, "inheritrange"); ir && *ir > 0.0 && tag == "position") {
    const auto& lim = out_.tree.joints[static_cast<std::size_t>(joint)].limits;
    if (lim) {
      const double mid = 0.5 * (lim->lower + lim->upper), half = 0.5 * (lim->upper - lim->lower);
      s.ctrlrange = std::array<double, 2>{mid - *ir * half, mid + *ir * half};
    }
  }
  if (auto f = range("forcerange", "forcelimited")) {  // forces on L: torques gear f on q
    const double lo = (*f)[0] * gear, hi = (*f)[1] * gear;
    s.forcerange = std::array<double, 2>{std::min(lo, hi), std::max(lo, hi)};
  }
  return s;
}

}  // namespace taskmap::detail
