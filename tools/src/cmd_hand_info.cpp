// taskmap hand-info HAND [--png FILE] [--json]: what taskmap makes of a hand (URDF + sidecar):
// joints, limits, mimic couplings, preshape and closing, palm frame, approach axis, rho, and
// warnings about set-ups that cannot grasp; optionally a picture of the preshape and the
// closed hand in three views.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "build_command.hpp"
#include "command.hpp"
#include "hand_check.hpp"
#include "hand_picture.hpp"
#include "mesh_options.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/meshes/hand_model.hpp"
#include "taskmap/viz/hand_page.hpp"

namespace taskmap::cli {
namespace {

struct HandInfoArgs {
  std::string hand, png, html;
  bool json = false;
  bool force = false;
};

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

/// Everything hand-info reports, as JSON (the text output prints the same fields).
nlohmann::json describe(const HandModel& h, const HandReport& report) {
  nlohmann::json j;
  j["name"] = h.name();
  j["robot_name"] = h.robotName();
  j["urdf"] = h.urdfPath();
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
  return j;
}

/// One line per collision mesh part: pieces and volumes (cm^3).
void printCollisionMeshes(const nlohmann::json& j) {
  if (!j.contains("collision_meshes")) return;
  std::printf("collision meshes (volumes in cm^3: mesh / hull / pieces):\n");
  for (const auto& m : j["collision_meshes"]) {
    std::printf("  %-20s %s part %d: %d faces, %d convex piece%s, %.4g / %.4g / %.4g",
                m["link"].get<std::string>().c_str(), m["file"].get<std::string>().c_str(),
                m["part"].get<int>(), m["faces"].get<int>(), m["pieces"].get<int>(),
                m["pieces"].get<int>() == 1 ? "" : "s", 1e6 * m["mesh_volume"].get<double>(),
                1e6 * m["hull_volume"].get<double>(), 1e6 * m["pieces_volume"].get<double>());
    if (m["wrapped"].get<bool>())
      std::printf(" (not a clean solid: decomposed its alpha wrap, %d exact pieces)",
                  m["raw_pieces"].get<int>());
    else if (m["decomposed"].get<bool>() && m["raw_pieces"] == m["pieces"])
      std::printf(" (decomposed)");
    else if (m["decomposed"].get<bool>())
      std::printf(" (decomposed: %d exact pieces merged)", m["raw_pieces"].get<int>());
    else
      std::printf(" (hull: %s)", m["note"].get<std::string>().c_str());
    std::printf("\n");
  }
}

std::string v3(const nlohmann::json& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.4g, %.4g, %.4g)", v[0].get<double>(), v[1].get<double>(),
                v[2].get<double>());
  return buf;
}

void printText(const nlohmann::json& j) {
  std::printf("hand:           %s (URDF robot '%s')\n", j["name"].get<std::string>().c_str(),
              j["robot_name"].get<std::string>().c_str());
  std::printf("urdf:           %s\nsidecar:        %s\n", j["urdf"].get<std::string>().c_str(),
              j["sidecar"].get<std::string>().c_str());
  std::printf("joints:\n");
  for (const auto& e : j["joints"]) {
    std::printf("  %-24s %-9s", e["name"].get<std::string>().c_str(),
                e["type"].get<std::string>().c_str());
    if (e.contains("lower"))
      std::printf(" [%.4g, %.4g] axis %s", e["lower"].get<double>(), e["upper"].get<double>(),
                  v3(e["axis"]).c_str());
    if (e.contains("mimic"))
      std::printf("  mimics %s: q = %.4g q + %.4g", e["mimic"]["joint"].get<std::string>().c_str(),
                  e["mimic"]["multiplier"].get<double>(), e["mimic"]["offset"].get<double>());
    if (e.contains("actuated"))
      std::printf("  preshape %.4g, closed %.4g", e["preshape"].get<double>(),
                  e["closed"].get<double>());
    std::printf("\n");
  }
  std::printf("closing:       ");
  for (const auto& c : j["closing"])
    std::printf(" %s -> %.4g (speed %.3g);", c["joint"].get<std::string>().c_str(),
                c["target"].get<double>(), c["speed"].get<double>());
  std::printf("\npalm link:      %s\n", j["palm_link"].get<std::string>().c_str());
  std::printf("palm frame:     xyz %s m, rpy %s rad in the palm link\n",
              v3(j["palm_frame"]["xyz"]).c_str(), v3(j["palm_frame"]["rpy"]).c_str());
  std::printf("                xyz %s m, rpy %s rad in the URDF root\n",
              v3(j["root_to_palm"]["xyz"]).c_str(), v3(j["root_to_palm"]["rpy"]).c_str());
  std::printf("approach axis:  %s (palm frame)\n", v3(j["approach_axis"]).c_str());
  std::printf("rho:            %.4g m (rotation scale of the pose metric)\n",
              j["rotation_scale"].get<double>());
  std::printf("reach:          %.4g m (open hand, from the palm origin)\n",
              j["reach"].get<double>());
  std::printf("fingers:       ");
  for (auto it = j["fingers"].begin(); it != j["fingers"].end(); ++it)
    std::printf(" %s (%zu links);", it.key().c_str(), it.value().size());
  std::printf("\n");
  printCollisionMeshes(j);
  for (const auto& n : j["notes"])
    std::printf("note:           %s\n", n.get<std::string>().c_str());
  for (const auto& w : j["warnings"])
    std::printf("warning:        %s\n", w.get<std::string>().c_str());
}

void run(const HandInfoArgs& args) {
  const std::string urdf =
      std::filesystem::exists(args.hand) ? args.hand : bundledHandUrdf(args.hand);
  checkOutputPath(args.png, {urdf, handSidecarPath(urdf)}, OutputKind::kPng, args.force, "--png");
  const HandModel hand = HandModel::load(urdf);
  const HandReport report = checkHand(hand);
  const nlohmann::json j = describe(hand, report);
  if (!args.png.empty()) writeHandPicture(hand, args.png);
  if (!args.html.empty()) writeHandPage(hand, args.html);
  if (args.json)
    std::cout << j.dump(2) << "\n";
  else
    printText(j);
  if (!args.png.empty() && !args.json) std::printf("wrote:          %s\n", args.png.c_str());
  if (!args.html.empty() && !args.json) std::printf("wrote:          %s\n", args.html.c_str());
}

const CommandRegistrar kRegistrar("hand-info", [](CLI::App& app) {
  auto args = std::make_shared<HandInfoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "hand-info",
      "Show what taskmap makes of a hand: joints, limits, mimic couplings, preshape and closing, "
      "palm frame, approach axis, rho; warn about set-ups that cannot grasp (no finger reaches "
      "past the front of the palm or of geometry fixed to it; collision meshes that could not "
      "be decomposed), the warnings `build` prints before its trials");
  cmd->add_option("hand", args->hand, "hand URDF (with its <stem>.hand.json) or bundled name")
      ->required();
  cmd->add_option("--png", args->png,
                  "also draw the hand in its preshape and fully closed, three views each");
  cmd->add_option("--html", args->html,
                  "also write an interactive 3-D page (self-contained HTML): the hand open and "
                  "closed, palm frame, approach axis, one slider per joint");
  cmd->add_flag("--json", args->json, "print JSON instead of text");
  addPackagePathOption(cmd);
  cmd->add_flag("--force", args->force, "replace an existing --png file that is not a PNG");
  cmd->callback([args]() { run(*args); });
});

}  // namespace
}  // namespace taskmap::cli
