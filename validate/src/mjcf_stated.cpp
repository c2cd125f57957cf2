// The hand's stated dynamics in the hold test's scene (mjcf_stated.hpp).
#include "mjcf_stated.hpp"

#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

namespace taskmap::detail {
namespace {

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string attr(const char* name, double v) {
  return std::string(" ") + name + "=\"" + num(v) + "\"";
}

template <std::size_t N>
std::string attr(const char* name, const std::array<double, N>& v) {
  std::string s = std::string(" ") + name + "=\"";
  for (std::size_t i = 0; i < N; ++i) s += (i ? " " : "") + num(v[i]);
  return s + "\"";
}

}  // namespace

bool usesStated(const HandModel& hand, const HoldTestOptions& options) {
  return options.stated_dynamics && !hand.dynamics().source.empty();
}

std::string statedInertial(const HandModel& hand, int l, StatedUse* use) {
  ++use->links;
  const auto& links = hand.dynamics().links;
  if (!use->on || links.empty() || !links[static_cast<std::size_t>(l)] ||
      !(links[static_cast<std::size_t>(l)]->mass > 0.0))
    return "";
  const UrdfInertial& in = *links[static_cast<std::size_t>(l)];
  const Eigen::Matrix3d r = in.origin.linear();
  const Eigen::Matrix3d i = r * in.inertia * r.transpose();  // about the centre, link axes
  ++use->inertia;
  const Eigen::Vector3d c = in.origin.translation();
  return "<inertial pos=\"" + num(c.x()) + " " + num(c.y()) + " " + num(c.z()) + "\" mass=\"" +
         num(in.mass) + "\" fullinertia=\"" + num(i(0, 0)) + " " + num(i(1, 1)) + " " +
         num(i(2, 2)) + " " + num(i(0, 1)) + " " + num(i(0, 2)) + " " + num(i(1, 2)) + "\"/>";
}

std::string statedJoint(const HandModel& hand, int j, double damping, double armature,
                        StatedUse* use) {
  ++use->joints;
  JointDynamics d;
  if (use->on) d = hand.dynamics().joints[static_cast<std::size_t>(j)];
  use->damping += d.damping.has_value();
  use->armature += d.armature.has_value();
  use->frictionloss += d.frictionloss.has_value();
  use->stiffness += d.stiffness.has_value();
  std::string s = attr("damping", d.damping.value_or(damping)) +
                  attr("armature", d.armature.value_or(armature));
  if (d.frictionloss) s += attr("frictionloss", *d.frictionloss);
  if (d.stiffness) s += attr("stiffness", *d.stiffness);
  if (d.stiffness && d.springref) s += attr("springref", *d.springref);
  return s;
}

std::string statedActuator(const HandModel& hand, const std::string& name,
                           const std::string& joint_xml_name, int joint, double kp, double limit,
                           StatedUse* use) {
  ++use->actuated;
  ActuatorDynamics a;
  if (use->on) {
    const auto& stated = hand.dynamics().actuators[static_cast<std::size_t>(joint)];
    if (stated) a = *stated;
  }
  const HandJoint& j = hand.joints()[static_cast<std::size_t>(joint)];
  use->kp += a.kp.has_value();
  use->kv += a.kv.has_value();
  use->ctrlrange += a.ctrlrange.has_value();
  use->forcerange += a.forcerange.has_value();
  const double gain = a.kp.value_or(kp);
  const std::array<double, 2> ctrl = a.ctrlrange.value_or(std::array<double, 2>{j.lower, j.upper});
  // MuJoCo 2.2.2's <position> has no kv: a servo with a velocity gain is the <general> it stands
  // for (bias 0, -kp, -kv).
  const bool general = a.kv && *a.kv != 0.0;
  std::string s = std::string(general ? "<general" : "<position") + " name=\"" + name +
                  "\" joint=\"" + joint_xml_name + "\" ctrllimited=\"true\"" +
                  attr("ctrlrange", ctrl);
  if (general)
    s += " gaintype=\"fixed\" biastype=\"affine\"" + attr("gainprm", gain) + " biasprm=\"0 " +
         num(-gain) + " " + num(-*a.kv) + "\"";
  else
    s += attr("kp", gain);
  if (a.forcerange)
    s += " forcelimited=\"true\"" + attr("forcerange", *a.forcerange);
  else if (std::isfinite(limit))
    s += " forcelimited=\"true\"" + attr("forcerange", std::array<double, 2>{-limit, limit});
  return s + "/>";
}

std::string statedCoupling(const HandModel& hand, int j, const std::string& fallback,
                           StatedUse* use) {
  ++use->couplings;
  JointDynamics d;
  if (use->on) d = hand.dynamics().joints[static_cast<std::size_t>(j)];
  use->coupling_solref += d.coupling_solref.has_value();
  use->coupling_solimp += d.coupling_solimp.has_value();
  if (!d.coupling_solref && !d.coupling_solimp) return fallback;
  std::string s;
  if (d.coupling_solref) s += attr("solref", *d.coupling_solref);
  if (d.coupling_solimp) s += attr("solimp", *d.coupling_solimp);
  return s;
}

std::string statedContact(const HandModel& hand, int l, int k, double sliding, double torsional,
                          StatedUse* use) {
  ++use->shapes;
  if (!use->on) return "";
  const ShapeContact& c =
      hand.dynamics().shapes[static_cast<std::size_t>(l)][static_cast<std::size_t>(k)];
  std::string s;
  if (c.sliding || c.torsional || c.rolling) {
    ++use->friction;
    s += attr("friction",
              std::array<double, 3>{c.sliding.value_or(sliding), c.torsional.value_or(torsional),
                                    c.rolling.value_or(0.0001)});
  }
  if (c.solref) {
    ++use->solref;
    s += attr("solref", *c.solref);
  }
  if (c.solimp) {
    ++use->solimp;
    s += attr("solimp", *c.solimp);
  }
  return s;
}

std::string StatedUse::json(const HandModel& hand) const {
  nlohmann::ordered_json j;
  j["source"] = hand.modelFormat();
  j["used"] = on ? "the model's where stated, the protocol's elsewhere" : "the protocol's";
  auto count = [&](const char* key, int model, int of) { j[key] = {{"model", model}, {"of", of}}; };
  count("mass_inertia", inertia, links);
  count("damping", damping, joints);
  count("armature", armature, joints);
  count("frictionloss", frictionloss, joints);
  count("stiffness", stiffness, joints);
  count("kp", kp, actuated);
  count("kv", kv, actuated);
  count("ctrlrange", ctrlrange, actuated);
  count("forcerange", forcerange, actuated);
  count("coupling_solref", coupling_solref, couplings);
  count("coupling_solimp", coupling_solimp, couplings);
  count("geom_friction", friction, shapes);
  count("geom_solref", solref, shapes);
  count("geom_solimp", solimp, shapes);
  j["contact_excludes"] = {{"model", hand.dynamics().excluded_pairs.size()},
                           {"note", "not needed: the scene has no contacts between hand links"}};
  return j.dump();
}

}  // namespace taskmap::detail
