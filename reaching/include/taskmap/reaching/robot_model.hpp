#pragma once
/// @file robot_model.hpp
/// Kinematic tree of a robot (URDF: revolute, prismatic, fixed joints), its collision
/// primitives (capsules and sphere-swept rectangles, paper section 1.2.1.2), a hand mounted on a
/// flange through a fixed adapter, and environment bodies (table, object). Units: metres,
/// radians. Equations: docs/REACHING.md.

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/hands/hand_model.hpp"

namespace taskmap {

/// Kind of a collision primitive: a sphere-swept segment or a sphere-swept rectangle.
enum class PrimitiveType { kCapsule, kSweptRectangle };

/// A sphere-swept convex core (segment or rectangle) in its body frame. A sphere is a capsule
/// of half_u 0; a box becomes an inscribed sphere-swept rectangle (see fromBox).
struct Primitive {
  PrimitiveType type = PrimitiveType::kCapsule;        ///< kind
  Eigen::Vector3d center = Eigen::Vector3d::Zero();    ///< core centre, body frame, metres
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  ///< columns u, v, u x v, body frame
  double half_u = 0.0;  ///< half length of the segment / rectangle along u, metres (>= 0)
  double half_v = 0.0;  ///< half width of the rectangle along v (0 for a capsule), metres
  double radius = 0.0;  ///< sweep radius, metres (>= 0)

  /// Capsule from its segment end points p0, p1 (body frame) and radius. Throws Error on a
  /// negative or non-finite value.
  static Primitive capsule(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, double radius);
  /// Sphere-swept rectangle: centre, orthonormal axes (u, v, normal columns), half extents.
  static Primitive sweptRectangle(const Eigen::Vector3d& center, const Eigen::Matrix3d& axes,
                                  double half_u, double half_v, double radius);
  /// Box of full extents `size` at pose `origin` (body frame) as the inscribed sphere-swept
  /// rectangle: radius half the smallest extent, rectangle the other two extents less 2 radius
  /// (exact on the faces, edges rounded with that radius).
  static Primitive fromBox(const Eigen::Isometry3d& origin, const Eigen::Vector3d& size);
  /// Radius of the smallest sphere about center that contains the primitive, metres.
  double boundingRadius() const;
};

/// What a body belongs to: the robot arm, the mounted hand, or the environment.
enum class BodyRole { kRobot, kHand, kEnvironment };

/// One rigid body of the tree, bodies ordered parents first.
struct RobotBody {
  std::string name;  ///< unique body name (URDF link name, hand link name, scene name)
  int parent = -1;   ///< parent body index, -1 for the world
  BodyRole role = BodyRole::kRobot;  ///< robot, hand or environment
  /// Joint frame in the parent body frame (the world frame when parent is -1).
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  JointType joint = JointType::kFixed;              ///< motion of this body relative to its parent
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< unit joint axis, joint frame
  int dof = -1;                   ///< index into the configuration vector q, -1 if fixed
  std::vector<Primitive> shapes;  ///< collision primitives, body frame
  int chain_depth = 0;            ///< number of moving joints between this body and the world
  double mass = 0.0;  ///< kg, from the URDF <inertial> (0 for hand links and the environment)
  Eigen::Vector3d com = Eigen::Vector3d::Zero();  ///< centre of mass, body frame, metres
};

/// The hand's collision shapes in a robot model.
enum class HandShapes {
  /// One sphere-swept rectangle enclosing all the hand's link primitives at hand_q, in the
  /// palm frame (one primitive per body, as in the paper; the default).
  kEnvelope,
  kPerLink,  ///< every hand link keeps its own primitives (more pairs, tighter fit)
};

/// How a hand is mounted: the hand's palm frame in the flange body frame (the adapter).
struct HandMount {
  std::string flange;  ///< body the hand is attached to (e.g. "fer_link8")
  /// Palm frame (HandModel::palmFrame, on the palm link) expressed in the flange frame.
  Eigen::Isometry3d palm_in_flange = Eigen::Isometry3d::Identity();
  /// Hand joint values (HandModel::jointNames order); empty means the hand's preshape.
  Eigen::VectorXd hand_q;
  /// How the hand collides with the robot and the scene.
  HandShapes hand_shapes = HandShapes::kEnvelope;
};

/// The mount of `hand` on the arm body `flange`: the palm frame in the flange frame from the
/// hand's sidecar "mount" (HandModel::mount). Throws Error naming the hand, its sidecar and
/// the key to add (or `option`, the caller's way to give a mount) when the sidecar has none:
/// another hand's adapter would put the palm somewhere else, silently.
HandMount mountFromSidecar(const HandModel& hand, const std::string& flange,
                           const std::string& option = "--mount \"x y z qw qx qy qz\"");

/// A robot: bodies, degrees of freedom with limits. Cheap to copy; const methods thread-safe.
class RobotModel {
 public:
  /// Loads a URDF; collision primitives come from <dir>/<stem>.capsules.json when present
  /// (format: reaching/robots/panda/panda.capsules.json), else from the URDF's boxes,
  /// cylinders (as enclosing capsules) and spheres (meshes are skipped: listed in warnings()).
  /// Continuous joints get limits -pi..pi. Throws Error naming the file on unreadable or
  /// invalid input (floating/planar joints, mimic joints, zero axes, missing limits).
  static RobotModel load(const std::string& urdf_path);
  /// The shipped Panda arm (reaching/robots/panda) with the reference humanoid hand
  /// (meshes/hands/humanoid) on its flange.
  /// @param robots_dir the folder holding panda/ (reaching/robots, or <data dir>/robots)
  /// @param hands_dir the folder holding humanoid/ (meshes/hands, or <data dir>/hands)
  static RobotModel pandaWithHumanoidHand(const std::string& robots_dir,
                                          const std::string& hands_dir);
  /// The adapter used by pandaWithHumanoidHand: palm faces the flange x axis, fingers along the
  /// flange z axis, wrist 2 cm beyond the flange.
  static HandMount humanoidMountOnPanda();

  /// Mounts a hand: each hand link becomes a fixed body "hand/<link>" (role kHand) under
  /// mount.flange, with its boxes as sphere-swept rectangles, cylinders and spheres as
  /// capsules, convex meshes as enclosing spheres; adds a body "palm" at the palm frame, which
  /// carries the enveloping primitive with HandShapes::kEnvelope. Throws Error on an unknown
  /// flange, a second hand, or a wrong hand_q size.
  void mountHand(const HandModel& hand, const HandMount& mount);
  /// Adds an environment body fixed in the world at `pose`. Throws Error on a duplicate name.
  int addEnvironmentBody(const std::string& name, const Eigen::Isometry3d& pose,
                         const std::vector<Primitive>& shapes);

  const std::string& name() const { return name_; }                        ///< URDF robot name
  const std::vector<RobotBody>& bodies() const { return bodies_; }         ///< parents first
  int dofs() const { return static_cast<int>(dof_names_.size()); }         ///< size of q
  const std::vector<std::string>& dofNames() const { return dof_names_; }  ///< joint names
  const Eigen::VectorXd& lower() const { return lower_; }  ///< lower position limits
  const Eigen::VectorXd& upper() const { return upper_; }  ///< upper position limits
  /// Velocity limits (rad/s or m/s); +inf where the URDF gives none.
  const Eigen::VectorXd& velocityLimits() const { return velocity_; }
  /// Index of a body by name, -1 if none.
  int bodyIndex(const std::string& name) const;
  /// Index of a body by name; throws Error listing the bodies when absent.
  int requireBody(const std::string& name) const;
  /// Index of the palm body of the mounted hand, -1 without a hand.
  int palmBody() const { return palm_body_; }
  /// Messages about skipped input (mesh collision geometry without a capsule model).
  const std::vector<std::string>& warnings() const { return warnings_; }
  /// For each body, the dofs on its path to the world, root first.
  const std::vector<std::vector<int>>& bodyDofs() const { return body_dofs_; }
  /// Configuration in the middle of the joint ranges.
  Eigen::VectorXd midConfiguration() const { return 0.5 * (lower_ + upper_); }

 private:
  friend struct UrdfRobotReader;
  int addBody(RobotBody body);
  void rebuildPaths();

  std::string name_;
  std::vector<RobotBody> bodies_;
  std::vector<std::string> dof_names_;
  Eigen::VectorXd lower_, upper_, velocity_;
  std::vector<std::vector<int>> body_dofs_;
  std::vector<std::string> warnings_;
  int palm_body_ = -1;
};

}  // namespace taskmap
