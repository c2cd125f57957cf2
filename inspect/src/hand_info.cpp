// What `taskmap hand-info` reports about a hand (hand_info.hpp).
#include "taskmap/inspect/hand_info.hpp"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

/// printf into out.
__attribute__((format(printf, 2, 3))) void appendf(std::string& out, const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  va_list copy;
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, fmt, copy);
  va_end(copy);
  if (n > 0) {
    const std::size_t old = out.size();
    out.resize(old + static_cast<std::size_t>(n) + 1);
    std::vsnprintf(&out[old], static_cast<std::size_t>(n) + 1, fmt, args);
    out.resize(old + static_cast<std::size_t>(n));
  }
  va_end(args);
}

nlohmann::json vec(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

const char* typeName(JointType t) {
  switch (t) {
    case JointType::kRevolute:
      return "revolute";
    case JointType::kPrismatic:
      return "prismatic";
    case JointType::kFixed:
      return "fixed";
  }
  return "fixed";
}

/// Roll, pitch, yaw (URDF convention R = Rz(y) Ry(p) Rx(r)) of a rotation, radians.
Eigen::Vector3d rpyOf(const Eigen::Matrix3d& r) {
  const Eigen::Vector3d ypr = r.eulerAngles(2, 1, 0);
  return {ypr[2], ypr[1], ypr[0]};
}

/// How many links, joints, actuated joints and collision shapes have dynamics the model states.
nlohmann::json statedDynamics(const HandModel& h) {
  const HandDynamics& d = h.dynamics();
  int masses = 0, damped = 0, movable = 0, servos = 0, frictions = 0, shapes = 0;
  for (const auto& l : d.links) masses += l.has_value();
  for (std::size_t j = 0; j < d.joints.size(); ++j) {
    if (h.joints()[j].type == JointType::kFixed) continue;
    ++movable;
    damped += d.joints[j].damping.has_value();
    servos += d.actuators[j] && d.actuators[j]->kp.has_value();
  }
  for (const auto& link : d.shapes)
    for (const ShapeContact& c : link) {
      ++shapes;
      frictions += c.sliding.has_value();
    }
  return {{"masses", masses},
          {"links", d.links.size()},
          {"damping", damped},
          {"movable_joints", movable},
          {"servo_gains", servos},
          {"actuated_joints", h.jointNames().size()},
          {"geom_friction", frictions},
          {"shapes", shapes},
          {"contact_excludes", d.excluded_pairs.size()}};
}

/// Everything hand-info reports, as JSON (the text output prints the same fields).
nlohmann::json describe(const HandModel& h, const HandReport& report) {
  nlohmann::json j;
  j["name"] = h.name();
  j["robot_name"] = h.robotName();
  j["urdf"] = h.urdfPath();
  j["format"] = h.modelFormat();
  j["sidecar"] = h.sidecarPath();
  j["urdf_sha256"] = h.urdfSha256();
  const auto names = h.jointNames();
  const Eigen::VectorXd pre = h.preshape(), closed = closedConfiguration(h);
  for (const HandJoint& jt : h.joints()) {
    nlohmann::json e = {{"name", jt.name},
                        {"type", typeName(jt.type)},
                        {"parent", h.links()[static_cast<std::size_t>(jt.parent_link)].name},
                        {"child", h.links()[static_cast<std::size_t>(jt.child_link)].name}};
    if (jt.type != JointType::kFixed) {
      e["lower"] = jt.lower;
      e["upper"] = jt.upper;
      e["axis"] = vec(jt.axis);
      const auto d = static_cast<std::size_t>(jt.driver);
      if (jt.mimic) {
        e["mimic"] = {{"joint", names[d]}, {"multiplier", jt.multiplier}, {"offset", jt.offset}};
      } else {
        e["actuated"] = true;
        e["preshape"] = pre[static_cast<Eigen::Index>(d)];
        e["closed"] = closed[static_cast<Eigen::Index>(d)];
      }
    }
    j["joints"].push_back(e);
  }
  for (const ClosingJoint& c : h.closing())
    j["closing"].push_back({{"joint", names[static_cast<std::size_t>(c.joint)]},
                            {"target", c.target},
                            {"speed", c.speed}});
  j["palm_link"] = h.links()[static_cast<std::size_t>(h.palmLink())].name;
  j["palm_frame"] = {{"xyz", vec(h.palmFrame().translation())},
                     {"rpy", vec(rpyOf(h.palmFrame().linear()))}};
  j["root_to_palm"] = {{"xyz", vec(h.rootToPalm().translation())},
                       {"rpy", vec(rpyOf(h.rootToPalm().linear()))}};
  j["approach_axis"] = vec(h.approachAxis());
  j["rotation_scale"] = h.rotationScale();
  j["reach"] = h.reach();
  j["squeeze"] = h.squeeze();
  for (std::size_t f = 0; f < h.fingerNames().size(); ++f) {
    nlohmann::json links = nlohmann::json::array();
    for (const HandLink& l : h.links())
      if (l.finger == static_cast<int>(f)) links.push_back(l.name);
    j["fingers"][h.fingerNames()[f]] = links;
  }
  for (const HandLink& l : h.links())
    j["links"].push_back(
        {{"name", l.name},
         {"shapes", l.shapes.size()},
         {"palm", l.palm},
         {"finger", l.finger >= 0
                        ? nlohmann::json(h.fingerNames()[static_cast<std::size_t>(l.finger)])
                        : nlohmann::json(nullptr)}});
  for (const CollisionMeshInfo& m : h.collisionMeshes())
    j["collision_meshes"].push_back({{"link", m.link},
                                     {"file", m.file},
                                     {"part", m.part},
                                     {"faces", m.faces},
                                     {"pieces", m.pieces},
                                     {"decomposed", m.decomposed},
                                     {"wrapped", m.wrapped},
                                     {"raw_pieces", m.raw_pieces},
                                     {"mesh_volume", m.mesh_volume},
                                     {"hull_volume", m.hull_volume},
                                     {"pieces_volume", m.pieces_volume},
                                     {"note", m.note}});
  j["warnings"] = report.warnings;
  j["notes"] = report.notes;
  // What loading the model skipped (an MJCF's missing visual meshes, unused actuators) and what
  // it states about its dynamics (docs/HANDS.md).
  j["model_warnings"] = h.loadWarnings();
  if (!h.dynamics().source.empty()) j["stated_dynamics"] = statedDynamics(h);
  return j;
}

/// One line per collision mesh part: pieces and volumes (cm^3).
void printCollisionMeshes(std::string& out, const nlohmann::json& j) {
  if (!j.contains("collision_meshes")) return;
  appendf(out, "collision meshes (volumes in cm^3: mesh / hull / pieces):\n");
  for (const auto& m : j["collision_meshes"]) {
    appendf(out, "  %-20s %s part %d: %d faces, %d convex piece%s, %.4g / %.4g / %.4g",
            m["link"].get<std::string>().c_str(), m["file"].get<std::string>().c_str(),
            m["part"].get<int>(), m["faces"].get<int>(), m["pieces"].get<int>(),
            m["pieces"].get<int>() == 1 ? "" : "s", 1e6 * m["mesh_volume"].get<double>(),
            1e6 * m["hull_volume"].get<double>(), 1e6 * m["pieces_volume"].get<double>());
    if (m["wrapped"].get<bool>())
      appendf(out, " (not a clean solid: decomposed its alpha wrap, %d exact pieces)",
              m["raw_pieces"].get<int>());
    else if (m["decomposed"].get<bool>() && m["raw_pieces"] == m["pieces"])
      appendf(out, " (decomposed)");
    else if (m["decomposed"].get<bool>())
      appendf(out, " (decomposed: %d exact pieces merged)", m["raw_pieces"].get<int>());
    else
      appendf(out, " (hull: %s)", m["note"].get<std::string>().c_str());
    appendf(out, "\n");
  }
}

std::string v3(const nlohmann::json& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.4g, %.4g, %.4g)", v[0].get<double>(), v[1].get<double>(),
                v[2].get<double>());
  return buf;
}

std::string printText(const nlohmann::json& j) {
  std::string out;
  const bool mjcf = j["format"] == "MJCF";
  appendf(out, "hand:           %s (%s '%s')\n", j["name"].get<std::string>().c_str(),
          mjcf ? "MJCF model" : "URDF robot", j["robot_name"].get<std::string>().c_str());
  appendf(out, "%s           %s\nsidecar:        %s\n",
          mjcf ? "mjcf:" : "urdf:", j["urdf"].get<std::string>().c_str(),
          j["sidecar"].get<std::string>().c_str());
  if (j.contains("stated_dynamics")) {
    const auto& d = j["stated_dynamics"];
    appendf(out,
            "dynamics:       the model states %d of %d masses, %d of %d servo gains, damping of "
            "%d of %d joints, friction of %d of %d shapes, %d contact exclusions (the "
            "validator uses them: docs/VALIDATION.md)\n",
            d["masses"].get<int>(), d["links"].get<int>(), d["servo_gains"].get<int>(),
            d["actuated_joints"].get<int>(), d["damping"].get<int>(),
            d["movable_joints"].get<int>(), d["geom_friction"].get<int>(), d["shapes"].get<int>(),
            d["contact_excludes"].get<int>());
  }
  appendf(out, "joints:\n");
  for (const auto& e : j["joints"]) {
    appendf(out, "  %-24s %-9s", e["name"].get<std::string>().c_str(),
            e["type"].get<std::string>().c_str());
    if (e.contains("lower"))
      appendf(out, " [%.4g, %.4g] axis %s", e["lower"].get<double>(), e["upper"].get<double>(),
              v3(e["axis"]).c_str());
    if (e.contains("mimic"))
      appendf(out, "  mimics %s: q = %.4g q + %.4g", e["mimic"]["joint"].get<std::string>().c_str(),
              e["mimic"]["multiplier"].get<double>(), e["mimic"]["offset"].get<double>());
    if (e.contains("actuated"))
      appendf(out, "  preshape %.4g, closed %.4g", e["preshape"].get<double>(),
              e["closed"].get<double>());
    appendf(out, "\n");
  }
  appendf(out, "closing:       ");
  for (const auto& c : j["closing"])
    appendf(out, " %s -> %.4g (speed %.3g);", c["joint"].get<std::string>().c_str(),
            c["target"].get<double>(), c["speed"].get<double>());
  appendf(out, "\npalm link:      %s\n", j["palm_link"].get<std::string>().c_str());
  appendf(out, "palm frame:     xyz %s m, rpy %s rad in the palm link\n",
          v3(j["palm_frame"]["xyz"]).c_str(), v3(j["palm_frame"]["rpy"]).c_str());
  appendf(out, "                xyz %s m, rpy %s rad in the URDF root\n",
          v3(j["root_to_palm"]["xyz"]).c_str(), v3(j["root_to_palm"]["rpy"]).c_str());
  appendf(out, "approach axis:  %s (palm frame)\n", v3(j["approach_axis"]).c_str());
  appendf(out, "rho:            %.4g m (rotation scale of the pose metric)\n",
          j["rotation_scale"].get<double>());
  appendf(out, "reach:          %.4g m (open hand, from the palm origin)\n",
          j["reach"].get<double>());
  appendf(out, "fingers:       ");
  for (auto it = j["fingers"].begin(); it != j["fingers"].end(); ++it)
    appendf(out, " %s (%zu links);", it.key().c_str(), it.value().size());
  appendf(out, "\n");
  printCollisionMeshes(out, j);
  for (const auto& n : j["notes"])
    appendf(out, "note:           %s\n", n.get<std::string>().c_str());
  for (const auto& w : j["model_warnings"])
    appendf(out, "model:          %s\n", w.get<std::string>().c_str());
  for (const auto& w : j["warnings"])
    appendf(out, "warning:        %s\n", w.get<std::string>().c_str());
  return out;
}

}  // namespace

void HandInfoOptions::validate() const {
  if (!std::filesystem::is_regular_file(hand))
    throw Error("hand '" + hand + "' does not exist; give a hand URDF");
}

HandInfo handInfo(const HandModel& hand) {
  HandInfo info;
  info.report = checkHand(hand);
  const nlohmann::json j = describe(hand, info.report);
  info.json = j.dump(2);
  info.text = printText(j);
  if (!info.report.warnings.empty()) {
    info.status = HandInfo::Status::kWarnings;
    info.message = info.report.warnings.front();
  }
  return info;
}

HandInfo handInfo(const HandInfoOptions& options) {
  options.validate();
  return handInfo(HandModel::load(options.hand));
}

}  // namespace taskmap
