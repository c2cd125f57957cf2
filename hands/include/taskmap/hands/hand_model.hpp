#pragma once
/// @file hand_model.hpp
/// A robot hand: kinematics and convex collision shapes from a URDF or an MJCF file (urdfdom,
/// TinyXML, assimp, kept private; mjcf_model.hpp), the dynamics an MJCF states
/// (hand_dynamics.hpp), plus the grasping sidecar <stem>.hand.json (palm frame, approach axis,
/// preshape, closing motion, squeeze; format in meshes/hands/README.md). Units: metres, radians.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/hands/hand_dynamics.hpp"

namespace taskmap {

/// Kind of a convex collision shape.
enum class ShapeType { kBox, kCylinder, kSphere, kConvex };

/// One convex collision shape of a link, described by Eigen values only.
struct CollisionShape {
  ShapeType type = ShapeType::kBox;                          ///< primitive kind
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< shape frame in the link frame
  Eigen::Vector3d box_size = Eigen::Vector3d::Zero();  ///< kBox: full extents along x, y, z, metres
  double radius = 0.0;                                 ///< kCylinder, kSphere: radius, metres
  double length = 0.0;                  ///< kCylinder: length along the shape's z axis, metres
  std::vector<Eigen::Vector3d> points;  ///< kConvex: hull vertices in the shape frame, metres

  /// Smallest extent of the shape (box side, diameter, hull width along its axes), metres.
  double thickness() const;
  /// Radius of a sphere about the shape frame origin that contains the shape, metres.
  double boundingRadius() const;
};

/// How one connected part of a link's collision mesh became convex shapes
/// (HandModel::collisionMeshes(); sidecar "collision", meshes/hands/README.md).
struct CollisionMeshInfo {
  std::string link;            ///< URDF link name
  std::string file;            ///< mesh file as written in the URDF
  int part = 0;                ///< index of the connected part in the file (file order)
  int first_shape = 0;         ///< index of its first shape in HandLink::shapes
  int pieces = 1;              ///< convex shapes it became (1: its convex hull)
  bool decomposed = false;     ///< true when the pieces come from the convex decomposition
  bool wrapped = false;        ///< true when the decomposition was of the part's alpha wrap
  double mesh_volume = 0.0;    ///< volume enclosed by the part's faces, m^3 (0 when open)
  double hull_volume = 0.0;    ///< volume of its convex hull, m^3
  double pieces_volume = 0.0;  ///< summed volume of its convex shapes, m^3
  int faces = 0;               ///< faces of the part in the file
  int raw_pieces = 0;          ///< pieces of the exact decomposition before merging (0: none)
  /// Why the hull was kept ("decomposition off", "nearly convex", or a failure: then a warning),
  /// or why the alpha wrap was decomposed.
  std::string note;
  bool warning = false;  ///< true when decomposition was wanted but failed
};

/// Kind of a URDF joint as used here (continuous joints are revolute with +-pi limits).
enum class JointType { kRevolute, kPrismatic, kFixed };

/// A link of the hand tree.
struct HandLink {
  std::string name;                    ///< URDF link name
  int parent_joint = -1;               ///< index into HandModel::joints(), -1 for the root
  std::vector<CollisionShape> shapes;  ///< convex collision shapes (may be empty)
  bool palm = false;                   ///< rigidly attached to the palm link (palm included)
  int finger = -1;                     ///< index into HandModel::fingerNames(), -1 if none
};

/// A URDF joint. Joint value q: radians (revolute) or metres (prismatic).
struct HandJoint {
  std::string name;                                          ///< URDF joint name
  JointType type = JointType::kFixed;                        ///< kind
  int parent_link = -1;                                      ///< index into HandModel::links()
  int child_link = -1;                                       ///< index into HandModel::links()
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  ///< joint frame in the parent link
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();           ///< unit, joint frame
  double lower = 0.0;  ///< lower limit (after mimic mapping: of this joint's own value)
  double upper = 0.0;  ///< upper limit
  /// Index into HandModel::jointNames() of the actuated joint driving this one, -1 if fixed.
  int driver = -1;
  double multiplier = 1.0;  ///< q = multiplier * q_driver + offset (1, 0 for actuated joints)
  double offset = 0.0;      ///< see multiplier
  bool mimic = false;       ///< true when the URDF declares <mimic>
};

/// How the hand meets the object before it closes (sidecar "grasp.mode").
enum class GraspMode {
  kPalm,       ///< approach until the palm touches, press it, close (power grasp; default)
  kFingertip,  ///< approach until a link touches or the palm is `standoff` from the object;
               ///< close without palm contact (pinch / fingertip grasp)
};

/// How one actuated joint closes.
struct ClosingJoint {
  int joint = -1;       ///< index into HandModel::jointNames()
  double target = 0.0;  ///< closed limit the joint moves toward (its lower or upper limit)
  double speed = 1.0;   ///< relative speed (> 0); only ratios between joints matter
};

/// A hand model: immutable after load, cheap to copy, every const method thread-safe.
class HandModel {
 public:
  /// Loads the hand model file <urdf_path> and its sidecar <same dir>/<stem>.hand.json (or an
  /// explicit one). The file is a URDF, or an MJCF (MuJoCo XML: its first element is <mujoco>;
  /// read by mjcf_model.hpp). Throws Error naming the file and the element on unreadable files,
  /// unknown links or joints, links without collision geometry where the sidecar needs it, and
  /// bad values.
  static HandModel load(const std::string& urdf_path, const std::string& sidecar_path = "");
  /// The URDF alone, without a sidecar (for drafting one, hand_draft.hpp): links, joints,
  /// limits and collision shapes (default collision options); the palm is the root link with
  /// the identity palm frame (linkPoses gives root-frame poses), the preshape every joint's
  /// value nearest 0; no closing motion, no fingers. Throws Error as load does for the URDF.
  static HandModel loadKinematics(const std::string& urdf_path);

  /// Hand name for maps and titles: the sidecar's "name", else the URDF robot name, else (when
  /// that is a generic word such as "hand" or "gripper") the URDF file stem.
  const std::string& name() const;
  const std::string& robotName() const;  ///< robot name from the URDF
  /// SHA-256 of the model file's bytes (URDF or MJCF; an MJCF's <include>s not counted), hex.
  const std::string& urdfSha256() const;
  const std::string& urdfPath() const;     ///< the model file read (URDF or MJCF)
  const std::string& modelFormat() const;  ///< "URDF" or "MJCF": the model file's format
  /// What the model states about its dynamics (an MJCF's masses, gains, damping, friction...;
  /// empty for a URDF).
  const HandDynamics& dynamics() const;
  /// What loading the model skipped and why (an MJCF's missing visual meshes, unused actuators).
  const std::vector<std::string>& loadWarnings() const;
  const std::string& sidecarPath() const;       ///< the sidecar file read
  std::vector<std::string> jointNames() const;  ///< actuated joints: order of every joint vector
  Eigen::VectorXd preshape() const;             ///< open preshape, one value per joint name
  /// Unit, palm frame: direction the hand moves toward the object.
  Eigen::Vector3d approachAxis() const;
  /// Palm-to-fingertip length in metres (rho hint): the sidecar's rotation_scale, else the
  /// largest distance from the palm origin to a point of a finger link in the preshape.
  double rotationScale() const;
  /// Radius of the sphere about the palm origin that contains the open hand (preshape), metres.
  double reach() const;

  /// Lower limits of the actuated joints (jointNames() order), radians or metres.
  Eigen::VectorXd lowerLimits() const;
  /// Upper limits of the actuated joints (jointNames() order), radians or metres.
  Eigen::VectorXd upperLimits() const;
  /// Every link of the URDF tree; Contact::link indexes this list.
  const std::vector<HandLink>& links() const;
  /// Every URDF joint, parents before children.
  const std::vector<HandJoint>& joints() const;
  /// Index of the palm link in links().
  int palmLink() const;
  /// Palm frame expressed in the palm link frame.
  const Eigen::Isometry3d& palmFrame() const;
  /// Palm frame expressed in the URDF root link frame (constant: the palm is fixed to the root).
  const Eigen::Isometry3d& rootToPalm() const;
  /// The closing motion: which actuated joints close, toward which limit, how fast.
  const std::vector<ClosingJoint>& closing() const;
  /// Squeeze after contact, metres: how far each contact is pressed into the object.
  double squeeze() const;
  /// Groups of closing() indices that the sidecar's "coupled" key declares one mechanism (they
  /// keep closing together, like joints coupled by a URDF <mimic>); empty when none.
  const std::vector<std::vector<int>>& coupledClosing() const;
  /// How the hand grasps (sidecar "grasp.mode", default kPalm).
  GraspMode graspMode() const;
  /// Fingertip grasps: the approach stops when the palm is this far from the object, metres
  /// (sidecar "grasp.standoff"; 0 when the sidecar does not set it, see hasStandoff).
  double standoff() const;
  /// How the hand sits on an arm (sidecar "mount": {"xyz", "rpy"}): the palm frame in the
  /// arm's flange frame (the flange's z out of the arm), metres and radians; empty when the
  /// sidecar does not say (reaching then needs the mount from its caller).
  const std::optional<Eigen::Isometry3d>& mount() const;
  /// True when the sidecar sets "grasp.standoff" (else the simulator derives one from the hand:
  /// resolveStandoff in grasp_sim).
  bool hasStandoff() const;
  /// Every connected part of every collision mesh and how it became convex shapes (URDF order).
  const std::vector<CollisionMeshInfo>& collisionMeshes() const;
  /// Finger names from the sidecar (HandLink::finger indexes this list).
  const std::vector<std::string>& fingerNames() const;
  /// Index into links() of a link by name, -1 if none.
  int linkIndex(const std::string& name) const;
  /// Index into jointNames() of an actuated joint by name, -1 if none.
  int jointIndex(const std::string& name) const;

  /// Pose of every link (links() order) in the palm frame for actuated joint values q
  /// (jointNames() order; values are clamped to the limits). Throws Error on a size mismatch.
  std::vector<Eigen::Isometry3d> linkPoses(const Eigen::VectorXd& q) const;
  /// linkPoses(q) into *poses (resized to links().size(); no allocation once it has that size).
  void linkPoses(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>* poses) const;
  /// Values of every URDF joint (joints() order) for actuated values q (not clamped).
  Eigen::VectorXd allJointValues(const Eigen::VectorXd& q) const;
  /// For each link, the actuated joints (jointNames() indices) that move it relative to the palm.
  const std::vector<std::vector<int>>& linkDrivers() const;
  /// For each actuated joint, an upper bound on the speed (m per unit of q) of any point of any
  /// link it moves: lever arm for revolute joints (times |mimic multiplier|), 1 for prismatic.
  const std::vector<double>& jointLevers() const;

 private:
  std::string name_, robot_name_, sha_, urdf_path_, sidecar_path_, format_ = "URDF";
  HandDynamics dynamics_;
  std::vector<std::string> load_warnings_;
  std::vector<HandLink> links_;
  std::vector<CollisionMeshInfo> collision_meshes_;
  std::vector<HandJoint> joints_;
  std::vector<std::string> actuated_;
  std::vector<double> lower_, upper_;
  Eigen::VectorXd preshape_;
  Eigen::Vector3d approach_ = Eigen::Vector3d::UnitZ();
  double rotation_scale_ = 0.0;
  double reach_ = 0.0;
  int palm_link_ = -1;
  Eigen::Isometry3d palm_frame_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d root_to_palm_ = Eigen::Isometry3d::Identity();    // palm frame in root frame
  Eigen::Isometry3d palm_from_root_ = Eigen::Isometry3d::Identity();  // its inverse
  std::vector<ClosingJoint> closing_;
  double squeeze_ = 0.0;
  std::vector<std::string> fingers_;
  std::vector<std::vector<int>> link_drivers_;
  std::vector<double> levers_;
  std::vector<std::vector<int>> coupled_;
  GraspMode grasp_mode_ = GraspMode::kPalm;
  double standoff_ = 0.0;
  bool has_standoff_ = false;
  std::optional<Eigen::Isometry3d> mount_;

  friend struct HandModelBuilder;
  friend struct HandGraspingKeys;
};

}  // namespace taskmap
