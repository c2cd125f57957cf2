#pragma once
/// @file closing_check.hpp
/// Closing with the object free to move (docs/METHOD.md §4d): after the kinematic trial found
/// a grasp's joints, a Bullet dynamics world (float64, private) replays how a position-controlled
/// hand closes on a free object: the hand a fixed-base multibody at the palm pose (revolute and
/// prismatic joints, mimic joints driven with their driver's target), the object a free rigid
/// body of the hold test's mass made of its convex pieces, no gravity, friction 0.6. The joints
/// are driven from a pregrasp (pregrasp_fraction of the way from the preshape to the grasp)
/// through the grasp to the squeeze target (squeeze_fraction), as the hold test of
/// docs/VALIDATION.md closes; the check then measures how far the object moved and turned. Links
/// that touch first and push the object away before the stored contacts form fail it.
/// Units: metres, radians, kilograms, newtons, seconds.

#include <array>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "taskmap/core/pose.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {

/// Whether and how a build runs the closing check.
enum class ClosingCheckMode {
  kOff,      ///< no check (default)
  kClosing,  ///< simulate the closing with the object free; refuse grasps that move it
  /// kClosing, then push the object with push_force along -x, +x, -y, +y, -z, +z of the object
  /// frame, one after the other (push_duration each, the hand holding its squeeze target)
  kPushes,
};

/// Stable lowercase name: "off", "closing", "pushes".
const char* toString(ClosingCheckMode mode);
/// Parses a name of toString; throws Error listing the names for anything else.
ClosingCheckMode closingCheckModeFromString(const std::string& name);

/// The check's numbers. Drive, mass, friction and closing path are the hold test's
/// (docs/VALIDATION.md, "Parameters"); the thresholds are the check's own.
struct ClosingCheckOptions {
  ClosingCheckMode mode = ClosingCheckMode::kOff;  ///< off by default
  double object_mass = 0.1;                        ///< kg, the free object's mass
  double friction = 0.6;                           ///< Coulomb friction of hand-object contacts
  /// m: torsional friction of hand-object contacts (a contact resists turning about its normal
  /// with at most this times its normal force; the hold test's 0.02; 0: none)
  double torsional_friction = 0.0;
  double kp_revolute = 5.0;          ///< N m / rad, position gain of revolute joints
  double damping_revolute = 0.1;     ///< N m s / rad, revolute joint damping
  double kp_prismatic = 20000.0;     ///< N / m, position gain of prismatic joints
  double damping_prismatic = 100.0;  ///< N s / m, prismatic joint damping
  double jaw_force = 70.0;           ///< N, force limit of each prismatic joint (parallel jaw)
  /// A gripper whose only actuated joint is revolute (a Robotiq 2F-85's linkage) presses each
  /// finger tip with jaw_force, as in the hold test (hands' jointDrives); false: kp_revolute
  /// without a force limit on every revolute joint (maps built before 2026-11-27)
  bool revolute_gripper_force = true;
  double link_density = 800.0;     ///< kg / m^3, hand links' mass from their shapes
  double pregrasp_fraction = 0.9;  ///< start: this far from the preshape to the grasp
  double squeeze_fraction = 1.1;   ///< end target: this far from the preshape past the grasp
  double closing_time = 0.8;       ///< s, pregrasp to grasp and grasp to squeeze, half each
  int interpolation_stages = 10;   ///< control targets per half (linear steps)
  double timestep = 0.004;         ///< s, control period
  int substeps = 4;                ///< Bullet steps per control period (>= 1)
  int solver_iterations = 10;      ///< Bullet constraint solver iterations per step (>= 1)
  /// Start each step's solve of the joint drives and limits from their previous impulses
  /// (Bullet's SOLVER_USE_ARTICULATED_WARMSTARTING): a grip that a chain of drive, contact,
  /// object, contact, drive transmits builds up over the steps instead of within one step's
  /// iterations
  bool warm_start_drives = false;
  /// Overrides for parallel grippers: hands with a driven prismatic joint (parallel jaws), and
  /// one-joint revolute grippers with revolute_gripper_force. Their grip is a chain
  /// (drive, contact, object, contact, drive) that the solver's Gauss-Seidel iterations resolve
  /// slowly, and two opposed pads leave an axis that only torsional friction holds: with few
  /// iterations and none, the jaws press too lightly and a 1 N push slides or turns the object
  /// out of a grip that holds in the hold test (docs/VALIDATION.md, second round).
  struct Jaws {
    int solver_iterations = 0;         ///< >= 0; 0: ClosingCheckOptions::solver_iterations
    double torsional_friction = -1.0;  ///< m; < 0: ClosingCheckOptions::torsional_friction
    bool warm_start_drives = false;    ///< warm-start the drives (also when warm_start_drives is)
  } jaws;
  /// Bullet's contact error reduction (btContactSolverInfo::m_erp2): the share of a
  /// penetration removed per step (the stored grasps start pressed in by the squeeze).
  double contact_erp = 0.2;
  /// Steps of the quasi-static start (the object's velocity zeroed after each) that remove the
  /// hand's overlap with the object before the closing (0: none; docs/METHOD.md §4d).
  int max_settle_steps = 50;
  /// The contact error reduction during the quasi-static start (the object's velocity is zeroed
  /// after each of its steps, so a larger share only removes the overlap in fewer steps)
  double settle_erp = 0.2;
  double push_force = 1.0;     ///< N, kPushes: the hold test's push (10 x 0.1 kg)
  double push_duration = 0.2;  ///< s per direction (at most, with rest_speed > 0), kPushes
  /// kPushes: the order of the pushes, a permutation of the directions 0..5 (-x, +x, -y, +y,
  /// -z, +z of the object frame); each push starts where the one before it left the object
  std::array<int, 6> push_order{0, 1, 2, 3, 4, 5};
  /// m/s: a push ends early once the object's centre of mass moves slower than this (and it
  /// turns slower than rest_speed / 0.05 m, rad/s) for rest_steps steps in a row: the hand
  /// holds the push in equilibrium (0: every push lasts push_duration)
  double rest_speed = 0.0;
  int rest_steps = 2;  ///< steps (of timestep / substeps) at rest that end a push early (>= 1)
  /// With rest_speed > 0: a push also ends (passed) once the object, were the hand to let go,
  /// could not leave a threshold before the push's end: its origin moving on at the current
  /// velocity plus the push's acceleration push_force / object_mass, its rotation at the
  /// current spin (docs/METHOD.md §4d, "Free-body bound")
  bool push_free_bound = false;
  /// m/s, with push_free_bound: the bound ends a push only while the object's origin has moved
  /// slower than this on average since the push began (0: always)
  double push_bound_creep = 0.0;
  /// m: the grasp fails when the object's origin moves this far from its start (closing and
  /// pushes)
  double max_translation = 0.01;
  double max_rotation = 0.2617993877991494;  ///< rad (15 deg): or turns this far
  double max_penetration = 0.01;             ///< m: a hand starting deeper inside the object fails
  int object_max_pieces = 64;  ///< convex pieces of a non-convex object (ConvexPiecesOptions)
  double margin = 5e-4;        ///< m, Bullet collision margin of every shape
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
  /// The early-verdict settings (docs/METHOD.md §4d, docs/history/validation-2026-11.md "A cheaper
  /// closing check"): 8 ms steps, 4 solver iterations, closing 0.1 s (2 x 5 stages), at most 10
  /// settle steps at erp 0.8, pushes of at most 0.05 s that end at rest (5 mm/s for 2 steps) or at
  /// the first step past a threshold; about 30x cheaper than the defaults, mode kPushes. Jaws:
  /// 20 iterations, torsional friction 0.02 m (the hold test's), drives warm-started.
  static ClosingCheckOptions earlyVerdict();
};

/// Outcome of the check for one grasp.
struct ClosingCheckResult {
  bool holds = false;  ///< the object stayed within both thresholds
  /// The object origin's displacement when the check ended (object frame at the start), m
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();
  double translation = 0.0;          ///< |displacement|, m
  double rotation = 0.0;             ///< the object's rotation when the check ended, rad
  double initial_penetration = 0.0;  ///< deepest hand-object overlap at the pregrasp, m
  bool unstable = false;             ///< non-finite state (counts as not holding)
  /// Largest distance between a link origin placed by Bullet and by HandModel::linkPoses at
  /// the pregrasp (m; a consistency check of the multibody's kinematics).
  double placement_error = 0.0;
  int failed_push = -1;   ///< kPushes: index (-x, +x, -y, +y, -z, +z) of the push that failed
  int steps = 0;          ///< Bullet steps taken (the check stops once the object left a threshold)
  int settle_steps = 0;   ///< of steps: the quasi-static start
  int closing_steps = 0;  ///< of steps: the closing
  /// kPushes: of steps, those of each push (-x, +x, -y, +y, -z, +z; 0 for pushes not run)
  std::array<int, 6> push_steps{};
};

/// Runs the check for one hand and one object. Construction builds what every trial shares (the
/// object's convex pieces and shapes, the link shapes and masses, the multibody's joint
/// layout); check() builds its own dynamics world, is const, thread-safe, and its result depends
/// on its arguments only.
class ClosingChecker {
 public:
  /// @param object the solid (its mass properties shape the free body); @param hand the hand.
  /// Throws Error for invalid options or an unusable object mesh.
  ClosingChecker(const ObjectModel& object, const HandModel& hand,
                 const ClosingCheckOptions& options);
  ~ClosingChecker();
  ClosingChecker(const ClosingChecker&) = delete;
  ClosingChecker& operator=(const ClosingChecker&) = delete;

  /// Checks a grasp: palm frame `palm` in the object frame, actuated joints `joints`
  /// (HandModel::jointNames() order). Throws Error on a size mismatch.
  ClosingCheckResult check(const Pose& palm, const Eigen::VectorXd& joints) const;
  /// Convex pieces the object became.
  int objectPieces() const;
  /// The options in force.
  const ClosingCheckOptions& options() const;

  struct Model;  ///< private (Bullet shapes)

 private:
  std::unique_ptr<Model> model_;
};

}  // namespace taskmap
