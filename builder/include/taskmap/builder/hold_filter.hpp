#pragma once
/// @file hold_filter.hpp
/// The build's hold filter: before a simulated grasp is scored, the squeeze-balance test
/// (quality/squeeze_balance.hpp) asks whether the hand, position-controlled towards a squeeze
/// past the grasp as the physics hold test closes it (docs/VALIDATION.md), presses the free
/// object into equilibrium and resists the test pushes. Off by default. Grasps that fail are not
/// stored (trial outcome `unbalanced`) and cost no wrench hull. Equations: docs/METHOD.md §4b.

#include <vector>

#include <Eigen/Core>

#include "taskmap/core/contact.hpp"
#include "taskmap/core/pose.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/quality/squeeze_balance.hpp"

namespace taskmap {

/// How the actuators press and which grasps pass (defaults: the hold test's protocol).
struct HoldFilterOptions {
  /// Run the filter (`taskmap build --hold-filter`). Off by default: measured, it raises the
  /// hold rate of some hand x object pairs and costs stored grasps per CPU-second on all
  /// (docs/VALIDATION.md, "Grasps that hold without the validator").
  bool enabled = false;
  double kp_revolute = 5.0;       ///< N m / rad, position gain of revolute joints
  double squeeze_fraction = 1.1;  ///< the squeeze target, from the preshape past the grasp
  double jaw_force = 70.0;        ///< N, force limit of each parallel jaw (prismatic joints)
  double kp_prismatic = 20000.0;  ///< N / m, position gain of prismatic joints
  /// true: a gripper whose only actuated joint is revolute presses each finger tip with
  /// jaw_force, as in the hold test (hands' actuatorDrives). Off by default: measured on the
  /// real Robotiq 2F-85 (docs/VALIDATION.md, "One drive for the validator, the closing check and
  /// the hold filter"), with the real drive the balance passes nearly every grasp (its failures
  /// are losses while closing, which a static balance cannot see); with kp_revolute it refuses
  /// the grasps that need strong forces, and predicts the validator better.
  bool revolute_gripper_force = false;
  SqueezeBalanceOptions balance;  ///< friction, cone edges, pushes, tolerances
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
};

/// The drive of a grasp's contacts: each contact's Jacobian (from its link's chain of joints,
/// mimic multipliers included), each actuated joint's effort at the grasp (revolute:
/// kp (q_sq - q), q_sq = q0 + squeeze_fraction (q - q0) clamped to the joint's limits;
/// prismatic: the same with kp_prismatic, at most jaw_force times the jaws it moves) and lever
/// (HandModel::jointLevers(), 1 for prismatic joints); a one-joint revolute gripper's effort
/// is its drive's (hands' actuatorDrives: the tips press with at most jaw_force each). `palm` is
/// the palm frame in the object frame, `joints` the grasp's actuated joint values, contacts in the
/// object frame.
SqueezeDrive squeezeDrive(const HandModel& hand, const Pose& palm, const Eigen::VectorXd& joints,
                          const std::vector<Contact>& contacts, const HoldFilterOptions& options);

/// N: the default least squeeze force of a build (BuildOptions::min_squeeze_force): the hold
/// test's 1 N push over twice its friction 0.6, the force two opposing contacts must be pressed
/// with for their friction to resist the push (docs/METHOD.md §4e).
inline constexpr double kDefaultMinSqueezeForce = 1.0 / (2.0 * 0.6);

/// N: the largest force with which the squeeze presses one contact into the object. Over the
/// contacts c (outward normals n_c) and actuated joints a whose effort e_a moves c into the
/// object (e_a J_c,a . n_c < 0), the effort over the contact's lever about the joint,
/// |e_a| / |J_c,a|; 0 when no effort presses a contact. `drive` from squeezeDrive for the same
/// contacts (docs/METHOD.md §4e).
double squeezeForce(const std::vector<Contact>& contacts, const SqueezeDrive& drive);

/// The squeeze force (squeezeForce) of a grasp with the hold test's drive (HoldFilterOptions'
/// defaults, a one-joint revolute gripper pressing each tip with the jaw force): palm in the
/// object frame, joints in HandModel::jointNames() order, contacts in the object frame.
double graspSqueezeForce(const HandModel& hand, const Pose& palm, const Eigen::VectorXd& joints,
                         const std::vector<Contact>& contacts);

}  // namespace taskmap
