// Robot model: primitives, bodies, hand mounting, environment bodies.
#include "taskmap/reaching/robot_model.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <utility>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

bool finiteNonNegative(double x) {
  return std::isfinite(x) && x >= 0.0;
}

/// Unit vector orthogonal to a unit vector d.
Eigen::Vector3d orthogonalTo(const Eigen::Vector3d& d) {
  const Eigen::Vector3d other =
      std::abs(d.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return d.cross(other).normalized();
}

/// Sphere-swept rectangle inscribed in the palm-frame bounding box of the given primitives
/// (each with its link pose in the palm frame): radius half the box's smallest extent.
Primitive envelope(
    const std::vector<std::pair<Eigen::Isometry3d, std::vector<Primitive>>>& shapes) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& [pose, list] : shapes) {
    for (const Primitive& p : list) {
      const Eigen::Matrix3d a = pose.linear() * p.axes;
      const Eigen::Vector3d c = pose * p.center;
      for (int su = -1; su <= 1; su += 2) {
        for (int sv = -1; sv <= 1; sv += 2) {
          const double hv = p.type == PrimitiveType::kSweptRectangle ? p.half_v : 0.0;
          const Eigen::Vector3d x = c + su * p.half_u * a.col(0) + sv * hv * a.col(1);
          lo = lo.cwiseMin(x - Eigen::Vector3d::Constant(p.radius));
          hi = hi.cwiseMax(x + Eigen::Vector3d::Constant(p.radius));
        }
      }
    }
  }
  Eigen::Isometry3d box = Eigen::Isometry3d::Identity();
  box.translation() = 0.5 * (lo + hi);
  return Primitive::fromBox(box, hi - lo);
}

}  // namespace

Primitive Primitive::capsule(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double radius) {
  if (!p0.allFinite() || !p1.allFinite() || !finiteNonNegative(radius))
    throw Error("capsule: end points must be finite and the radius finite and >= 0");
  Primitive p;
  p.type = PrimitiveType::kCapsule;
  p.center = 0.5 * (p0 + p1);
  const Eigen::Vector3d d = p1 - p0;
  const double len = d.norm();
  const Eigen::Vector3d u = len > 1e-12 ? Eigen::Vector3d(d / len) : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d v = orthogonalTo(u);
  p.axes.col(0) = u;
  p.axes.col(1) = v;
  p.axes.col(2) = u.cross(v);
  p.half_u = 0.5 * len;
  p.radius = radius;
  return p;
}

Primitive Primitive::sweptRectangle(const Eigen::Vector3d& center, const Eigen::Matrix3d& axes,
                                    double half_u, double half_v, double radius) {
  if (!center.allFinite() || !finiteNonNegative(half_u) || !finiteNonNegative(half_v) ||
      !finiteNonNegative(radius))
    throw Error("swept rectangle: centre, half extents and radius must be finite, extents >= 0");
  if (!axes.allFinite() || (axes.transpose() * axes - Eigen::Matrix3d::Identity()).norm() > 1e-6)
    throw Error("swept rectangle: axes must be an orthonormal matrix (columns u, v, normal)");
  Primitive p;
  p.type = PrimitiveType::kSweptRectangle;
  p.center = center;
  p.axes = axes;
  p.half_u = half_u;
  p.half_v = half_v;
  p.radius = radius;
  return p;
}

Primitive Primitive::fromBox(const Eigen::Isometry3d& origin, const Eigen::Vector3d& size) {
  if (!size.allFinite() || size.minCoeff() < 0.0)
    throw Error("box: extents must be finite and >= 0");
  int thin = 0;
  size.minCoeff(&thin);
  const int a = (thin + 1) % 3, b = (thin + 2) % 3;
  const double r = 0.5 * size[thin];
  Eigen::Matrix3d axes;
  axes.col(0) = origin.linear().col(a);
  axes.col(1) = origin.linear().col(b);
  axes.col(2) = origin.linear().col(thin);
  return sweptRectangle(origin.translation(), axes, std::max(0.0, 0.5 * size[a] - r),
                        std::max(0.0, 0.5 * size[b] - r), r);
}

double Primitive::boundingRadius() const {
  return std::hypot(half_u, half_v) + radius;
}

int RobotModel::bodyIndex(const std::string& name) const {
  for (size_t i = 0; i < bodies_.size(); ++i)
    if (bodies_[i].name == name) return static_cast<int>(i);
  return -1;
}

int RobotModel::requireBody(const std::string& name) const {
  const int i = bodyIndex(name);
  if (i >= 0) return i;
  std::string names;
  for (const RobotBody& b : bodies_) names += (names.empty() ? "" : ", ") + b.name;
  throw Error("robot '" + name_ + "' has no body '" + name + "'; bodies: " + names);
}

int RobotModel::addBody(RobotBody body) {
  if (bodyIndex(body.name) >= 0)
    throw Error("robot '" + name_ + "': a body named '" + body.name +
                "' exists already; give the new body another name");
  assert(body.parent < static_cast<int>(bodies_.size()));
  body.chain_depth = (body.parent >= 0 ? bodies_[body.parent].chain_depth : 0) +
                     (body.joint == JointType::kFixed ? 0 : 1);
  bodies_.push_back(std::move(body));
  rebuildPaths();
  return static_cast<int>(bodies_.size()) - 1;
}

void RobotModel::rebuildPaths() {
  body_dofs_.assign(bodies_.size(), {});
  for (size_t i = 0; i < bodies_.size(); ++i) {
    const RobotBody& b = bodies_[i];
    if (b.parent >= 0) body_dofs_[i] = body_dofs_[b.parent];
    if (b.dof >= 0) body_dofs_[i].push_back(b.dof);
  }
}

int RobotModel::addEnvironmentBody(const std::string& name, const Eigen::Isometry3d& pose,
                                   const std::vector<Primitive>& shapes) {
  if (!pose.matrix().allFinite()) throw Error("environment body '" + name + "': pose not finite");
  RobotBody body;
  body.name = name;
  body.role = BodyRole::kEnvironment;
  body.origin = pose;
  body.shapes = shapes;
  return addBody(std::move(body));
}

void RobotModel::mountHand(const HandModel& hand, const HandMount& mount) {
  if (palm_body_ >= 0)
    throw Error("robot '" + name_ + "' carries a hand already; mount one hand per flange model");
  const int flange = requireBody(mount.flange);
  const Eigen::VectorXd q = mount.hand_q.size() == 0 ? hand.preshape() : mount.hand_q;
  if (q.size() != static_cast<Eigen::Index>(hand.jointNames().size()))
    throw Error("hand mount: hand_q has " + std::to_string(q.size()) + " values, hand '" +
                hand.name() + "' has " + std::to_string(hand.jointNames().size()) + " joints");
  if (!mount.palm_in_flange.matrix().allFinite())
    throw Error("hand mount: the adapter transform is not finite");
  // linkPoses are in the palm frame; the palm frame sits at palm_in_flange on the flange.
  const std::vector<Eigen::Isometry3d> poses = hand.linkPoses(q);
  std::vector<std::pair<Eigen::Isometry3d, std::vector<Primitive>>> hand_shapes;
  for (size_t i = 0; i < hand.links().size(); ++i) {
    const HandLink& link = hand.links()[i];
    RobotBody body;
    body.name = "hand/" + link.name;
    body.parent = flange;
    body.role = BodyRole::kHand;
    body.origin = mount.palm_in_flange * poses[i];
    for (const CollisionShape& s : link.shapes) {
      switch (s.type) {
        case ShapeType::kBox:
          body.shapes.push_back(Primitive::fromBox(s.origin, s.box_size));
          break;
        case ShapeType::kCylinder: {
          const Eigen::Vector3d half = s.origin.linear().col(2) * (0.5 * s.length);
          body.shapes.push_back(Primitive::capsule(s.origin.translation() - half,
                                                   s.origin.translation() + half, s.radius));
          break;
        }
        case ShapeType::kSphere:
          body.shapes.push_back(
              Primitive::capsule(s.origin.translation(), s.origin.translation(), s.radius));
          break;
        case ShapeType::kConvex: {
          // Enclosing sphere of the hull about its centroid: conservative, one primitive.
          Eigen::Vector3d c = Eigen::Vector3d::Zero();
          for (const auto& p : s.points) c += p;
          c /= std::max<size_t>(1, s.points.size());
          double r = 0.0;
          for (const auto& p : s.points) r = std::max(r, (p - c).norm());
          const Eigen::Vector3d cw = s.origin * c;
          body.shapes.push_back(Primitive::capsule(cw, cw, r));
          break;
        }
      }
    }
    hand_shapes.emplace_back(poses[i], body.shapes);
    if (mount.hand_shapes == HandShapes::kEnvelope) body.shapes.clear();
    addBody(std::move(body));
  }
  RobotBody palm;
  palm.name = "palm";
  palm.parent = flange;
  palm.role = BodyRole::kHand;
  palm.origin = mount.palm_in_flange;
  bool any_shape = false;
  for (const auto& entry : hand_shapes) any_shape = any_shape || !entry.second.empty();
  if (mount.hand_shapes == HandShapes::kEnvelope && any_shape)
    palm.shapes.push_back(envelope(hand_shapes));
  palm_body_ = addBody(std::move(palm));
}

HandMount mountFromSidecar(const HandModel& hand, const std::string& flange,
                           const std::string& option) {
  if (!hand.mount()) {
    const std::string sidecar = hand.sidecarPath().empty() ? "its sidecar" : hand.sidecarPath();
    throw Error("hand '" + hand.name() + "' does not say how it is mounted on the arm: add " +
                "\"mount\": {\"xyz\": [x, y, z], \"rpy\": [r, p, y]} (its palm frame in the " +
                "flange frame, metres and radians) to " + sidecar + ", or give " + option);
  }
  HandMount m;
  m.flange = flange;
  m.palm_in_flange = *hand.mount();
  return m;
}

HandMount RobotModel::humanoidMountOnPanda() {
  HandMount m;
  m.flange = "fer_link8";
  // Columns: palm x, y, z in flange coordinates (palm y = flange z, palm z = flange x).
  Eigen::Matrix3d r;
  r << 0, 0, 1,  //
      1, 0, 0,   //
      0, 1, 0;
  m.palm_in_flange.linear() = r;
  // Wrist (palm y = -0.05) 2 cm beyond the flange; the 3 cm palm centred on the flange axis.
  m.palm_in_flange.translation() = Eigen::Vector3d(0.015, 0.0, 0.07);
  return m;
}

RobotModel RobotModel::pandaWithHumanoidHand(const std::string& robots_dir,
                                             const std::string& hands_dir) {
  RobotModel robot = load(robots_dir + "/panda/panda.urdf");
  robot.mountHand(HandModel::load(hands_dir + "/humanoid/humanoid.urdf"), humanoidMountOnPanda());
  return robot;
}

}  // namespace taskmap
