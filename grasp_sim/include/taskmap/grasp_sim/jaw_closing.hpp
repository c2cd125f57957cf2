#pragma once
/// @file jaw_closing.hpp
/// Where the jaws of a parallel-jaw gripper come to rest on an object when they close from open
/// at a fixed palm pose: the joint values of a grasp that a third party gives as a pose alone
/// (ACRONYM's Franka grasps, docs/ACRONYM.md). Geometry only, exact for the hand's collision
/// shapes and the object's triangles: each jaw swept along its closing direction until it first
/// touches the object (vertex-face, face-vertex and edge-edge contacts of the translating shapes);
/// the object, free to slide between the jaws, is pushed by the first jaw to touch until the
/// other one touches too, so that the jaws close by the sum of the two sweep distances. The palm
/// pose is not changed. Units: metres; joint values in metres (prismatic) as HandModel.

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "taskmap/core/pose.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {

/// How the jaws end when they close from open.
enum class JawClosingStatus : std::uint8_t {
  kClosed = 0,  ///< both jaws touch the object (after it slid between them)
  kMissed,      ///< a jaw's sweep passes the object, or the jaws reach their closed limit first
  /// A jaw already intersects the object with the jaws open (its sweep 0; the joint value
  /// where the other jaw touches too): a grasp whose approach would collide, kept for a
  /// simulation to resolve (a hold test's penetration check).
  kOverlaps,
};

/// Stable lowercase name: "closed", "missed", "overlaps".
const char* toString(JawClosingStatus status);

/// The closing of one grasp.
struct JawClosing {
  JawClosingStatus status = JawClosingStatus::kMissed;  ///< see JawClosingStatus
  /// Actuated joint values (HandModel::jointNames() order): the preshape with the closing joint
  /// where both jaws touch (kClosed; kOverlaps: where the jaw that does not intersect the
  /// object touches it, open when both intersect) or at its closed limit (kMissed).
  Eigen::VectorXd joints;
  /// Per jaw (JawCloser::jawNames() order): how far it travels toward the object before it
  /// touches it, the object held still, metres; +infinity when it passes the object, 0 when
  /// it intersects the object open.
  std::vector<double> sweep;
  /// How far the object slides along the first touching jaw's closing direction until the
  /// other jaw touches, metres (kClosed only; 0 for a centred object).
  double object_shift = 0.0;
};

/// Closes the jaws of one parallel-jaw hand on one object, at palm poses given by the caller.
/// A parallel-jaw hand: exactly one closing joint (HandModel::closing()), prismatic, whose
/// links lie on exactly two fingers that it translates in opposite directions (a URDF <mimic>
/// pair, as the Franka hand's). close() is const, thread-safe and deterministic.
class JawCloser {
 public:
  /// @param hand the gripper (copied); @param object the solid, metres, object frame (its mesh
  /// is copied). Throws Error naming the hand when it is not a parallel-jaw gripper.
  JawCloser(const HandModel& hand, const ObjectModel& object);
  ~JawCloser();
  JawCloser(JawCloser&&) noexcept;
  JawCloser& operator=(JawCloser&&) noexcept;

  /// The jaws closed from the hand's preshape (open) with the palm frame at `palm` (object
  /// frame), the palm held there.
  JawClosing close(const Pose& palm) const;
  /// The two jaws' finger names (HandModel::fingerNames()), in JawClosing::sweep order.
  const std::vector<std::string>& jawNames() const;
  /// Index into HandModel::jointNames() of the closing joint.
  int closingJoint() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace taskmap
