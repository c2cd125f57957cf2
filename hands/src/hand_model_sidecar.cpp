// HandModel loading, sidecar step: <stem>.hand.json (format in meshes/hands/README.md) gives the
// palm link and frame, approach axis, preshape, closing motion, squeeze and fingers.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>

#include "hand_grasping_keys.hpp"
#include "hand_model_build.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

Eigen::Vector3d vec3(const json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3) throw Error(where + " must be an array of 3 numbers");
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) {
    if (!j[static_cast<std::size_t>(i)].is_number()) throw Error(where + " must hold numbers");
    v[i] = j[static_cast<std::size_t>(i)].get<double>();
  }
  if (!v.allFinite()) throw Error(where + " must be finite");
  return v;
}

double number(const json& j, const std::string& where) {
  if (!j.is_number()) throw Error(where + " must be a number");
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw Error(where + " must be finite");
  return v;
}

/// Name lookups and checks against the URDF tree; S prefixes errors ("hand sidecar '<path>': ").
struct SidecarContext {
  const HandModel& h;
  std::string S;

  int link(const json& v, const std::string& where) const {
    if (!v.is_string()) throw Error(S + where + " must be a link name");
    const int li = h.linkIndex(v.get<std::string>());
    if (li < 0)
      throw Error(S + where + " names link '" + v.get<std::string>() + "', which '" + h.urdfPath() +
                  "' does not have");
    return li;
  }
  int joint(const json& v, const std::string& where) const {
    if (!v.is_string()) throw Error(S + where + " must be a joint name");
    const int ji = h.jointIndex(v.get<std::string>());
    if (ji < 0)
      throw Error(S + where + " names joint '" + v.get<std::string>() +
                  "', which is not an actuated (non-fixed, non-mimic) joint of '" + h.urdfPath() +
                  "'");
    return ji;
  }
  void needGeometry(int li, const std::string& role) const {
    const HandLink& l = h.links()[static_cast<std::size_t>(li)];
    if (l.shapes.empty())
      throw Error(S + role + " link '" + l.name + "' has no <collision> geometry in '" +
                  h.urdfPath() + "'");
  }
};

/// A frame {"xyz": [m], "rpy": [rad]} (URDF convention) read from sidecar key `key`.
Eigen::Isometry3d frameOf(const json& pf, const std::string& S, const std::string& key) {
  if (!pf.is_object()) throw Error(S + key + " must be an object with xyz and rpy");
  for (auto it = pf.begin(); it != pf.end(); ++it)
    if (it.key() != "xyz" && it.key() != "rpy")
      throw Error(S + key + ": unknown key '" + it.key() + "' (allowed: xyz, rpy)");
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
  if (pf.contains("xyz")) xyz = vec3(pf["xyz"], S + key + ".xyz");
  if (pf.contains("rpy")) rpy = vec3(pf["rpy"], S + key + ".rpy");
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = xyz;
  t.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return t;
}

/// Throws unless the palm link is the root or hangs from it by fixed joints only.
void checkPalmFixed(const HandModel& h, int palm, const std::string& S) {
  int li = palm;
  while (h.links()[static_cast<std::size_t>(li)].parent_joint >= 0) {
    const HandJoint& j =
        h.joints()[static_cast<std::size_t>(h.links()[static_cast<std::size_t>(li)].parent_joint)];
    if (j.type != JointType::kFixed)
      throw Error(S + "palm_link '" + h.links()[static_cast<std::size_t>(palm)].name +
                  "' is moved by joint '" + j.name +
                  "': the palm must be the URDF root or fixed to it");
    li = j.parent_link;
  }
}

/// Listed joints take their value, others their value nearest 0 within limits.
Eigen::VectorXd preshapeOf(const json& js, const SidecarContext& ctx,
                           const std::vector<double>& lower, const std::vector<double>& upper) {
  const std::size_t n = lower.size();
  Eigen::VectorXd q(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i)
    q[static_cast<Eigen::Index>(i)] = std::clamp(0.0, lower[i], upper[i]);
  if (!js.contains("preshape")) return q;
  const std::string& S = ctx.S;
  if (!js["preshape"].is_object()) throw Error(S + "preshape must map joint names to values");
  for (auto it = js["preshape"].begin(); it != js["preshape"].end(); ++it) {
    const int ji = ctx.joint(json(it.key()), "preshape");
    const double v = number(it.value(), S + "preshape." + it.key());
    const auto u = static_cast<std::size_t>(ji);
    if (v < lower[u] - 1e-12 || v > upper[u] + 1e-12)
      throw Error(S + "preshape." + it.key() + " = " + std::to_string(v) +
                  " is outside the joint limits [" + std::to_string(lower[u]) + ", " +
                  std::to_string(upper[u]) + "]");
    q[ji] = v;
  }
  return q;
}

std::vector<ClosingJoint> closingOf(const json& closing, const SidecarContext& ctx,
                                    const std::vector<double>& lower,
                                    const std::vector<double>& upper) {
  const std::string& S = ctx.S;
  if (!closing.is_array() || closing.empty())
    throw Error(S + "closing must be a non-empty array of {joint, toward, speed}");
  std::vector<ClosingJoint> out;
  std::set<int> seen;
  for (std::size_t c = 0; c < closing.size(); ++c) {
    const json& e = closing[c];
    const std::string where = "closing[" + std::to_string(c) + "]";
    if (!e.is_object() || !e.contains("joint"))
      throw Error(S + where + " must be an object with a joint");
    ClosingJoint cj;
    cj.joint = ctx.joint(e["joint"], where + ".joint");
    if (!seen.insert(cj.joint).second)
      throw Error(S + where + ".joint '" + e["joint"].get<std::string>() + "' is listed twice");
    const std::string toward = e.value("toward", std::string("upper"));
    const auto u = static_cast<std::size_t>(cj.joint);
    if (toward == "upper")
      cj.target = upper[u];
    else if (toward == "lower")
      cj.target = lower[u];
    else
      throw Error(S + where + ".toward must be \"lower\" or \"upper\", not \"" + toward + "\"");
    cj.speed = e.contains("speed") ? number(e["speed"], S + where + ".speed") : 1.0;
    if (!(cj.speed > 0.0)) throw Error(S + where + ".speed must be positive");
    out.push_back(cj);
  }
  return out;
}

/// The URDF robot name, or the URDF file stem when the robot name says nothing ("hand").
std::string displayName(const std::string& robot, const std::string& urdf_path) {
  static const std::set<std::string> kGeneric = {"",   "hand",         "gripper", "robot", "model",
                                                 "ee", "end_effector", "eef",     "tool",  "urdf"};
  std::string lower = robot;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (!kGeneric.count(lower)) return robot;
  return fs::path(urdf_path).stem().string();
}

}  // namespace

json HandModelBuilder::readSidecar(HandModel& h, const std::string& sidecar_arg) {
  std::string sidecar = sidecar_arg;
  if (sidecar.empty()) {
    const fs::path p(h.urdf_path_);
    sidecar = (p.parent_path() / (p.stem().string() + ".hand.json")).string();
  }
  h.sidecar_path_ = sidecar;
  const std::string text = readHandFile(sidecar, "hand sidecar");
  const std::string S = "hand sidecar '" + sidecar + "': ";
  json js;
  try {
    js = json::parse(text);
  } catch (const std::exception& e) {
    throw Error(S + "invalid JSON: " + e.what());
  }
  if (!js.is_object()) throw Error(S + "must be a JSON object");
  static const std::set<std::string> kKeys = {
      "palm_link", "palm_frame", "approach_axis",  "preshape",    "closing",
      "squeeze",   "fingers",    "rotation_scale", "description", "dimensions",
      "name",      "coupled",    "grasp",          "collision",   "mount"};
  for (auto it = js.begin(); it != js.end(); ++it)
    if (!kKeys.count(it.key()))
      throw Error(S + "unknown key '" + it.key() + "' (see meshes/hands/README.md)");
  for (const char* k : {"palm_link", "approach_axis", "closing", "squeeze", "fingers"})
    if (!js.contains(k)) throw Error(S + "missing required key '" + k + "'");
  return js;
}

void HandModelBuilder::applySidecar(HandModel& h, const json& js) {
  const SidecarContext ctx{h, "hand sidecar '" + h.sidecar_path_ + "': "};
  const std::string& S = ctx.S;
  h.name_ = displayName(h.robot_name_, h.urdf_path_);
  if (js.contains("name")) {
    if (!js["name"].is_string() || js["name"].get<std::string>().empty())
      throw Error(S + "name must be a non-empty string");
    h.name_ = js["name"].get<std::string>();
  }
  h.palm_link_ = ctx.link(js["palm_link"], "palm_link");
  ctx.needGeometry(h.palm_link_, "palm");
  if (js.contains("palm_frame")) h.palm_frame_ = frameOf(js["palm_frame"], S, "palm_frame");
  if (js.contains("mount")) h.mount_ = frameOf(js["mount"], S, "mount");
  checkPalmFixed(h, h.palm_link_, S);
  const Eigen::Vector3d approach = vec3(js["approach_axis"], S + "approach_axis");
  if (!(approach.norm() > 1e-9)) throw Error(S + "approach_axis must not be zero");
  h.approach_ = approach.normalized();
  h.preshape_ = preshapeOf(js, ctx, h.lower_, h.upper_);
  h.closing_ = closingOf(js["closing"], ctx, h.lower_, h.upper_);
  h.squeeze_ = number(js["squeeze"], S + "squeeze");
  if (h.squeeze_ < 0.0 || h.squeeze_ > 0.01) throw Error(S + "squeeze must be in [0, 0.01] metres");
  HandGraspingKeys::read(js, S, &h);

  if (!js["fingers"].is_object() || js["fingers"].empty())
    throw Error(S + "fingers must map finger names to arrays of link names");
  for (auto it = js["fingers"].begin(); it != js["fingers"].end(); ++it) {
    const int fi = static_cast<int>(h.fingers_.size());
    h.fingers_.push_back(it.key());
    if (!it.value().is_array() || it.value().empty())
      throw Error(S + "fingers." + it.key() + " must be a non-empty array of link names");
    for (const json& l : it.value()) {
      const int li = ctx.link(l, "fingers." + it.key());
      ctx.needGeometry(li, "finger");
      HandLink& hl = h.links_[static_cast<std::size_t>(li)];
      if (hl.finger >= 0) throw Error(S + "link '" + hl.name + "' belongs to two fingers");
      hl.finger = fi;
    }
  }
}

}  // namespace taskmap
