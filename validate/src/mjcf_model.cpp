// The hold test's scene as MJCF (MuJoCo 2.2.2's XML), written from the hand model and the
// object's convex pieces. Frames: world = palm frame; URDF link frames become body frames.
#include "mjcf_model.hpp"
#include "mjcf_stated.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <utility>

#include <Eigen/Geometry>

#include "taskmap/core/constants.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/hands/hand_drive.hpp"
#include "taskmap/hands/link_inertia.hpp"

namespace taskmap::detail {
namespace {

constexpr double kMinSize = 1e-5;  // MuJoCo refuses geoms of zero size (metres)

/// Full-precision number.
std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

/// Text safe inside an XML attribute value.
std::string xmlName(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string vec(const Eigen::Vector3d& v) {
  return num(v.x()) + " " + num(v.y()) + " " + num(v.z());
}

/// pos and quat attributes of a transform.
std::string frame(const Eigen::Isometry3d& t) {
  const Eigen::Quaterniond q(t.rotation());
  return "pos=\"" + vec(t.translation()) + "\" quat=\"" + num(q.w()) + " " + num(q.x()) + " " +
         num(q.y()) + " " + num(q.z()) + "\"";
}

/// The <inertial> of a link: the model's when it states one (mjcf_stated.hpp); else density x
/// shape volume at the volume-weighted centre of its shapes, the inertia of a solid sphere of the
/// shapes' extent (docs/VALIDATION.md, "The model").
std::string inertial(const HandModel& hand, int l, double density, StatedUse* use) {
  const std::string stated = statedInertial(hand, l, use);
  if (!stated.empty()) return stated;
  const LinkInertia m = linkInertia(hand.links()[static_cast<std::size_t>(l)], density);
  const std::string i = num(m.inertia);
  return "<inertial pos=\"" + vec(m.centre) + "\" mass=\"" + num(m.mass) + "\" diaginertia=\"" + i +
         " " + i + " " + i + "\"/>";
}

/// Cells along an extent of 2 h: round(2 h / patch), 1 to 4.
int cells(double h, double patch) {
  if (patch <= 0.0) return 1;
  return std::clamp(static_cast<int>(std::lround(2.0 * h / patch)), 1, 4);
}

/// A box as cells of about `patch` per side across its two largest extents (the faces a pad
/// presses with; one geom when patch is 0).
void boxGeoms(const CollisionShape& s, double patch, const std::string& extra,
              std::ostringstream* body, int* geoms) {
  const Eigen::Vector3d h = (0.5 * s.box_size).cwiseMax(kMinSize);
  Eigen::Index thin = 0;
  h.minCoeff(&thin);
  Eigen::Vector3i n(cells(h.x(), patch), cells(h.y(), patch), cells(h.z(), patch));
  n[thin] = 1;
  const Eigen::Vector3d c = h.cwiseQuotient(n.cast<double>());  // half extents of a cell
  for (int i = 0; i < n.x(); ++i)
    for (int j = 0; j < n.y(); ++j)
      for (int k = 0; k < n.z(); ++k) {
        const Eigen::Vector3d at =
            -h + Eigen::Vector3d(2 * i + 1, 2 * j + 1, 2 * k + 1).cwiseProduct(c);
        Eigen::Isometry3d t = s.origin;
        t.translation() += s.origin.linear() * at;
        *body << "<geom class=\"hand\" " << frame(t) << " type=\"box\" size=\"" << vec(c) << "\""
              << extra << "/>\n";
        ++*geoms;
      }
}

/// A cylinder as segments along its axis of at most `patch` length (one when patch is 0).
void cylinderGeoms(const CollisionShape& s, double patch, const std::string& extra,
                   std::ostringstream* body, int* geoms) {
  const double half = std::max(0.5 * s.length, kMinSize);
  const int n = cells(half, patch);
  for (int k = 0; k < n; ++k) {
    Eigen::Isometry3d t = s.origin;
    t.translation() += s.origin.linear() * Eigen::Vector3d(0, 0, -half + (2 * k + 1) * half / n);
    *body << "<geom class=\"hand\" " << frame(t) << " type=\"cylinder\" size=\""
          << num(std::max(s.radius, kMinSize)) << " " << num(half / n) << "\"" << extra << "/>\n";
    ++*geoms;
  }
}

/// Mesh assets and geoms of one link's shapes (with the contact parameters the hand states).
void linkGeoms(const HandModel& hand, int link_index, double patch, const HoldTestOptions& o,
               StatedUse* use, std::ostringstream* assets, std::ostringstream* body, int* geoms) {
  const HandLink& link = hand.links()[static_cast<std::size_t>(link_index)];
  for (std::size_t k = 0; k < link.shapes.size(); ++k) {
    const CollisionShape& s = link.shapes[k];
    const std::string extra = statedContact(hand, link_index, static_cast<int>(k),
                                            o.sliding_friction, o.torsional_friction, use);
    if (s.type == ShapeType::kBox) {
      boxGeoms(s, patch, extra, body, geoms);
      continue;
    }
    if (s.type == ShapeType::kCylinder) {
      cylinderGeoms(s, patch, extra, body, geoms);
      continue;
    }
    *body << "<geom class=\"hand\" " << frame(s.origin) << extra << " ";
    switch (s.type) {
      case ShapeType::kBox:
      case ShapeType::kCylinder:
        break;
      case ShapeType::kSphere:
        *body << "type=\"sphere\" size=\"" << num(std::max(s.radius, kMinSize)) << "\"/>";
        break;
      case ShapeType::kConvex: {
        const std::string name = "hand_" + std::to_string(link_index) + "_" + std::to_string(k);
        *assets << "<mesh name=\"" << name << "\" vertex=\"";
        for (const auto& p : s.points) *assets << vec(p) << " ";
        *assets << "\"/>\n";
        *body << "type=\"mesh\" mesh=\"" << name << "\"/>";
        break;
      }
    }
    *body << "\n";
    ++*geoms;
  }
}

/// True when a prismatic actuated joint moves link l (a parallel jaw's pad).
bool jawLink(const HandModel& hand, int l) {
  const std::vector<std::string> names = hand.jointNames();
  for (int a : hand.linkDrivers()[static_cast<std::size_t>(l)])
    for (const auto& j : hand.joints())
      if (j.name == names[static_cast<std::size_t>(a)] && j.type == JointType::kPrismatic)
        return true;
  return false;
}

/// The hand's body tree (iterative: any depth), its actuators and its mimic equalities.
void handTree(const HandModel& hand, const HoldTestOptions& o, StatedUse* use,
              std::ostringstream* assets, std::ostringstream* bodies, std::ostringstream* actuators,
              std::ostringstream* equalities, MjcfScene* scene) {
  const auto& links = hand.links();
  const auto& joints = hand.joints();
  const std::vector<std::string> actuated = hand.jointNames();
  std::vector<std::vector<int>> children(links.size());
  int root = -1;
  for (std::size_t j = 0; j < joints.size(); ++j)
    children[static_cast<std::size_t>(joints[j].parent_link)].push_back(static_cast<int>(j));
  for (std::size_t l = 0; l < links.size(); ++l)
    if (links[l].parent_joint < 0) root = static_cast<int>(l);
  if (root < 0) throw Error("hold test: hand '" + hand.name() + "' has no root link");
  const DriveOptions drive_options{o.kp_revolute, o.kp_prismatic, o.jaw_force,
                                   o.revolute_gripper_force};
  const RevoluteGripper gripper = revoluteGripper(hand, drive_options);
  // The gripper's linkage: the jaws' damping and armature mapped through it (its drive train),
  // its mimic constraints stiff (> 0: a revolute gripper with revolute_gripper_linkage).
  const double train = o.revolute_gripper_linkage ? gripper.squares : 0.0;
  // Stack of (link, next child); a link's body opens when pushed and closes when popped.
  std::vector<std::pair<int, std::size_t>> stack;
  auto open = [&](int l, const Eigen::Isometry3d& t) {
    const HandLink& link = links[static_cast<std::size_t>(l)];
    *bodies << "<body name=\"link_" << l << "\" " << frame(t) << ">\n"
            << inertial(hand, l, o.link_density, use) << "\n";
    if (link.parent_joint >= 0) {
      const HandJoint& j = joints[static_cast<std::size_t>(link.parent_joint)];
      if (j.type != JointType::kFixed) {
        const bool slide = j.type == JointType::kPrismatic;
        const double geared = !actuated.empty() && j.name == actuated[0] ? train : 0.0;
        *bodies << "<joint name=\"" << xmlName(j.name) << "\" type=\""
                << (slide ? "slide" : "hinge") << "\" axis=\"" << vec(j.axis)
                << "\" limited=\"true\" range=\"" << num(j.lower) << " " << num(j.upper) << "\""
                << statedJoint(
                       hand, link.parent_joint,
                       slide ? o.prismatic_damping : o.joint_damping + geared * o.prismatic_damping,
                       slide ? o.prismatic_armature
                             : o.revolute_armature + geared * o.prismatic_armature,
                       use)
                << "/>\n";
      }
    }
    int geoms = 0;
    // Jaw pads touch with patches: prismatic jaws, and a revolute gripper's finger links.
    const bool pad = jawLink(hand, l) || (train > 0.0 && link.finger >= 0);
    linkGeoms(hand, l, pad ? o.contact_patch : 0.0, o, use, assets, bodies, &geoms);
    scene->hand_geoms += geoms;
    ++scene->hand_bodies;
    stack.emplace_back(l, 0);
  };
  open(root, hand.rootToPalm().inverse());
  while (!stack.empty()) {
    auto& [l, next] = stack.back();
    if (next == children[static_cast<std::size_t>(l)].size()) {
      *bodies << "</body>\n";
      stack.pop_back();
      continue;
    }
    const HandJoint& j =
        joints[static_cast<std::size_t>(children[static_cast<std::size_t>(l)][next++])];
    open(j.child_link, j.origin);
  }
  for (std::size_t ji = 0; ji < joints.size(); ++ji) {
    const HandJoint& j = joints[ji];
    if (j.type == JointType::kFixed || j.driver < 0) continue;
    const std::string& driver = actuated[static_cast<std::size_t>(j.driver)];
    if (j.name == driver) continue;
    *equalities << "<joint joint1=\"" << xmlName(j.name) << "\" joint2=\"" << xmlName(driver)
                << "\" polycoef=\"" << num(j.offset) << " " << num(j.multiplier) << " 0 0 0\"";
    // A revolute gripper's four-bar is rigid: its constraints as stiff as MuJoCo allows (time
    // constant two steps) with MuJoCo Menagerie's 2F-85 impedance. The model's own when stated.
    const std::string rigid =
        train > 0.0 ? " solref=\"" + num(2.0 * o.timestep) + " 1\" solimp=\"0.95 0.99 0.001\""
                    : std::string();
    *equalities << statedCoupling(hand, static_cast<int>(ji), rigid, use) << "/>\n";
    ++scene->mimic_constraints;
  }
  scene->gripper_torque = gripper.torque;
  const std::vector<JointDrive> drives = actuatorDrives(hand, drive_options);
  for (std::size_t a = 0; a < actuated.size(); ++a) {
    int j = -1;
    for (std::size_t c = 0; c < joints.size(); ++c)
      if (joints[c].name == actuated[a]) j = static_cast<int>(c);
    if (j < 0) throw Error("hold test: actuated joint '" + actuated[a] + "' is not a URDF joint");
    *actuators << statedActuator(hand, "act_" + std::to_string(a),
                                 xmlName(joints[static_cast<std::size_t>(j)].name), j, drives[a].kp,
                                 drives[a].limit, use)
               << "\n";
    ++scene->actuators;
  }
}

/// The object: a free body with the solid's mass properties at options.object_mass.
void objectBody(const ObjectModel& object, const ConvexPieces& pieces, const HoldTestOptions& o,
                std::ostringstream* assets, std::ostringstream* bodies) {
  const MassProperties& mp = object.massProperties();
  const double density = o.object_mass / mp.volume;
  const Eigen::Matrix3d i = density * mp.inertia;
  *bodies << "<body name=\"" << kObjectBody << "\">\n<freejoint name=\"" << kObjectJoint
          << "\"/>\n<inertial pos=\"" << vec(mp.center_of_mass) << "\" mass=\""
          << num(o.object_mass) << "\" fullinertia=\"" << num(i(0, 0)) << " " << num(i(1, 1)) << " "
          << num(i(2, 2)) << " " << num(i(0, 1)) << " " << num(i(0, 2)) << " " << num(i(1, 2))
          << "\"/>\n";
  for (std::size_t k = 0; k < pieces.pieces.size(); ++k) {
    *assets << "<mesh name=\"object_" << k << "\" vertex=\"";
    for (const auto& p : pieces.pieces[k]) *assets << vec(p) << " ";
    *assets << "\"/>\n";
    *bodies << "<geom class=\"object\" type=\"mesh\" mesh=\"object_" << k << "\"/>\n";
  }
  *bodies << "</body>\n";
}

// The integrator's MJCF name: Euler (implicit in joint damping) stands for implicitfast unless a
// servo has a velocity gain, whose derivative implicitfast also takes (then implicit).
const char* mjcfIntegrator(const HoldTestOptions& o, const StatedUse& use) {
  if (o.integrator == HoldTestOptions::Integrator::kImplicit || use.kv > 0) return "implicit";
  return "Euler";
}

}  // namespace

MjcfScene writeMjcf(const HandModel& hand, const ObjectModel& object, const ConvexPieces& pieces,
                    const HoldTestOptions& o) {
  MjcfScene scene;
  std::ostringstream assets, bodies, actuators, equalities;
  StatedUse use;
  use.on = usesStated(hand, o);
  handTree(hand, o, &use, &assets, &bodies, &actuators, &equalities, &scene);
  if (!hand.dynamics().source.empty()) scene.hand_dynamics = use.json(hand);
  objectBody(object, pieces, o, &assets, &bodies);
  const std::string friction =
      num(o.sliding_friction) + " " + num(o.torsional_friction) + " 0.0001";
  std::ostringstream x;
  x << "<mujoco model=\"taskmap_hold_test\">\n"
    << "<compiler angle=\"radian\" inertiafromgeom=\"false\""
    // A model's stated inertias as MuJoCo compiles the model itself (the protocol's always are).
    << (use.inertia > 0 ? " balanceinertia=\"true\"" : "") << "/>\n"
    << "<option timestep=\"" << num(o.timestep) << "\" gravity=\"0 0 0\" integrator=\""
    << mjcfIntegrator(o, use) << "\""
    << " cone=\"elliptic\" impratio=\"" << num(o.impratio) << "\" noslip_iterations=\""
    << o.noslip_iterations << "\" iterations=\"" << o.solver_iterations << "\" tolerance=\""
    << num(o.solver_tolerance) << "\"/>\n"
    << "<size njmax=\"1000\" nconmax=\"250\"/>\n"
    << "<default>\n"
    // Hand geoms collide with the object only (contype 1 / conaffinity 2 against 2 / 1).
    << "<default class=\"hand\"><geom contype=\"1\" conaffinity=\"2\" condim=\"4\" friction=\""
    << friction << "\" solimp=\"0.5 0.99 0.0001\" solref=\"0.005 1\"/></default>\n"
    << "<default class=\"object\"><geom contype=\"2\" conaffinity=\"1\" condim=\"4\" friction=\""
    << friction << "\"/></default>\n"
    << "</default>\n"
    << "<asset>\n"
    << assets.str() << "</asset>\n"
    << "<worldbody>\n"
    << bodies.str() << "</worldbody>\n";
  if (scene.mimic_constraints > 0) x << "<equality>\n" << equalities.str() << "</equality>\n";
  x << "<actuator>\n" << actuators.str() << "</actuator>\n</mujoco>\n";
  scene.xml = x.str();
  return scene;
}

}  // namespace taskmap::detail

namespace taskmap {

std::string handDynamicsJson(const HandModel& hand, const HoldTestOptions& options) {
  if (hand.dynamics().source.empty()) return {};
  detail::MjcfScene scene;
  std::ostringstream assets, bodies, actuators, equalities;
  detail::StatedUse use;
  use.on = detail::usesStated(hand, options);
  detail::handTree(hand, options, &use, &assets, &bodies, &actuators, &equalities, &scene);
  return use.json(hand);
}

}  // namespace taskmap
