#pragma once
/// @file urdf_model.hpp
/// A URDF as plain data: the one URDF reader of the library, under which hands (HandModel) and
/// robots (RobotModel, reaching) are built. urdfdom parses it (kept private to hands); its
/// console messages are captured under one process-wide lock (console_bridge's output handler
/// is process-global) and quoted in the Error. Units: metres, radians.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace taskmap {

/// Geometry of a URDF <visual> or <collision> element (or of an MJCF geom), in that element's
/// origin frame.
struct UrdfGeometry {
  /// The URDF element: <box>, <cylinder>, <sphere> or <mesh>; kCapsule and kEllipsoid come from
  /// MJCF geoms only (mjcf_model.hpp).
  enum class Type { kBox, kCylinder, kSphere, kMesh, kCapsule, kEllipsoid };
  Type type = Type::kBox;                              ///< which element
  Eigen::Vector3d box_size = Eigen::Vector3d::Zero();  ///< kBox: full edge lengths, metres
  double radius = 0.0;                                 ///< kCylinder, kSphere, kCapsule: metres
  /// kCylinder: length along local z; kCapsule: length of its straight part along local z (the
  /// hemispheres add a radius at each end), metres.
  double length = 0.0;
  Eigen::Vector3d radii = Eigen::Vector3d::Zero();       ///< kEllipsoid: semi-axes x, y, z, metres
  std::string mesh_file;                                 ///< kMesh: filename as written
  Eigen::Vector3d mesh_scale = Eigen::Vector3d::Ones();  ///< kMesh: scale per axis
  /// kMesh: the mesh collides as the convex hull of all its vertices (MJCF: how MuJoCo collides
  /// a mesh geom), not part by part as a URDF mesh does.
  bool mesh_hull = false;
  /// kMesh with an empty mesh_file: the mesh's vertices (an MJCF <mesh vertex>), metres before
  /// mesh_scale.
  std::vector<Eigen::Vector3d> mesh_vertices;
};

/// One <visual> or <collision> element of a link.
struct UrdfShape {
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< shape frame in the link frame
  UrdfGeometry geometry;                                     ///< what the element holds
};

/// A link's <inertial>: mass and centre-of-mass frame.
struct UrdfInertial {
  double mass = 0.0;                                         ///< kg, as written (not checked)
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< centre-of-mass frame, link frame
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();         ///< kg m^2 about the centre of mass
};

/// A URDF link.
struct UrdfLink {
  std::string name;                      ///< link name
  int parent_joint = -1;                 ///< index into UrdfModel::joints, -1 for the root
  std::vector<UrdfShape> visuals;        ///< <visual> elements with geometry, URDF order
  std::vector<UrdfShape> collisions;     ///< <collision> elements with geometry, URDF order
  std::optional<UrdfInertial> inertial;  ///< when the link has <inertial>
};

/// The <joint type> of a URDF joint.
enum class UrdfJointType { kRevolute, kContinuous, kPrismatic, kFixed, kFloating, kPlanar };

/// A joint's <limit>.
struct UrdfLimits {
  double lower = 0.0;     ///< radians or metres
  double upper = 0.0;     ///< radians or metres
  double effort = 0.0;    ///< N m or N
  double velocity = 0.0;  ///< rad/s or m/s
};

/// A joint's <mimic>: q = multiplier * q_joint + offset.
struct UrdfMimic {
  std::string joint;        ///< name of the joint it follows
  double multiplier = 1.0;  ///< see UrdfMimic
  double offset = 0.0;      ///< radians or metres
};

/// A URDF joint.
struct UrdfJoint {
  std::string name;                                          ///< joint name
  UrdfJointType type = UrdfJointType::kFixed;                ///< <joint type>
  int parent_link = -1;                                      ///< index into UrdfModel::links
  int child_link = -1;                                       ///< index into UrdfModel::links
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< joint frame in the parent link
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();           ///< <axis xyz> as written, joint frame
  std::optional<UrdfLimits> limits;                          ///< when the joint has <limit>
  std::optional<UrdfMimic> mimic;                            ///< when the joint has <mimic>
};

/// A URDF as a tree: links depth-first from the root (links[0]; children in URDF order), and
/// joints[i] the parent joint of links[i + 1].
struct UrdfModel {
  std::string name;               ///< <robot name>
  std::vector<UrdfLink> links;    ///< depth-first from the root
  std::vector<UrdfJoint> joints;  ///< joints[i] is the parent joint of links[i + 1]
  /// Index of the joint named `name`, -1 if none.
  int jointIndex(const std::string& name) const;
};

/// Parses the URDF text `xml` of the file `path`. `what` names the file's role in messages
/// ("URDF", "robot URDF"). Throws Error "cannot parse <what> '<path>': <urdfdom's messages>"
/// when urdfdom refuses it, and "<what> '<path>': ..." when a link is not reachable from the
/// root. Thread-safe: one lock serialises every parse of the process.
UrdfModel parseUrdfModel(const std::string& xml, const std::string& path, const std::string& what);

}  // namespace taskmap
