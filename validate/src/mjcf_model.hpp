#pragma once
// Private to validate: the MJCF text of the hold test's scene. The world frame is the palm
// frame: the hand's root body sits at the palm-from-root transform, fixed; the object is a free
// body whose start pose is set per grasp. Conventions in docs/VALIDATION.md, "The model".
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/convex_pieces.hpp"
#include "taskmap/meshes/object_model.hpp"
#include "taskmap/validate/hold_test.hpp"

namespace taskmap::detail {

/// Names the MJCF gives to what the tester addresses by name.
inline constexpr const char* kObjectBody = "object";
inline constexpr const char* kObjectJoint = "object_free";

/// The MJCF document and what it holds.
struct MjcfScene {
  std::string xml;
  int hand_bodies = 0;
  int hand_geoms = 0;
  int actuators = 0;
  int mimic_constraints = 0;
  double gripper_torque = 0.0;  ///< N m, 0 unless the hand is a revolute gripper
  /// Which of the hand's stated dynamics the scene used (mjcf_stated.hpp, JSON); "" for a hand
  /// that states none (a URDF).
  std::string hand_dynamics;
};

/// Writes the scene: hand links as bodies (their convex shapes as geoms), one position
/// actuator per actuated joint (HandModel::jointNames() order), URDF mimic joints as joint
/// equality constraints, the object's convex pieces as mesh geoms of one free body with the
/// object's mass properties scaled to options.object_mass. Where the hand's model states its
/// dynamics (an MJCF: HandModel::dynamics()) and options.stated_dynamics is on, those replace the
/// protocol's (masses and inertias, joint damping, armature, friction loss, servo gains and
/// ranges, geom friction and contact softness, coupling softness; mjcf_stated.hpp).
MjcfScene writeMjcf(const HandModel& hand, const ObjectModel& object, const ConvexPieces& pieces,
                    const HoldTestOptions& options);

}  // namespace taskmap::detail
