#pragma once
/// @file hold_test.hpp
/// Does a grasp hold the object in physics? The DexGraspBench force-closure protocol (BODex,
/// ICRA 2025) run in MuJoCo (kept private): the hand's base fixed at the grasp's palm pose, its
/// joints position-controlled from a pregrasp through the grasp to a squeeze, then a push on
/// the object's centre of mass along each of the object frame's six axis directions; the grasp
/// holds when the object moves and turns less than the thresholds under every push. Protocol,
/// numbers and sources: docs/VALIDATION.md. Units: metres, radians, kilograms, newtons, seconds.

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/core/pose.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {

/// The protocol's numbers; defaults are DexGraspBench's (docs/VALIDATION.md, "Parameters").
struct HoldTestOptions {
  double object_mass = 0.1;          ///< kg, the object a free body of this mass
  double sliding_friction = 0.6;     ///< sliding friction coefficient of every geom
  double torsional_friction = 0.02;  ///< torsional friction, metres (MuJoCo's second friction)
  double timestep = 0.004;           ///< s
  /// How MuJoCo integrates the velocities (docs/VALIDATION.md, "The integrator").
  enum class Integrator : std::uint8_t {
    /// MuJoCo's `implicit`: implicit in every velocity-dependent force, the Coriolis and
    /// centrifugal forces included (the default: the labels of every map so far).
    kImplicit,
    /// DexGraspBench's `implicitfast`: implicit in the velocity-dependent forces of joint
    /// damping and servos, not in the Coriolis and centrifugal forces; about 1.3 times fewer
    /// CPU seconds per grasp. MuJoCo 2.2.2 lacks it; its Euler integrator, implicit in joint
    /// damping, computes the same for a scene whose servos have no velocity gain (every
    /// protocol scene), and a scene with one is integrated `implicit`.
    kImplicitFast,
  };
  Integrator integrator = Integrator::kImplicit;  ///< see Integrator
  double impratio = 10.0;                         ///< MuJoCo's frictional-to-normal impedance ratio
  int noslip_iterations = 2;                      ///< MuJoCo's no-slip solver iterations
  int solver_iterations = 100;     ///< MuJoCo's constraint solver iterations (its default)
  double solver_tolerance = 1e-8;  ///< MuJoCo's solver tolerance (its default)
  double kp_revolute = 5.0;        ///< N m / rad, position gain of revolute joints
  double joint_damping = 0.1;      ///< N m s / rad, damping of revolute joints
  double link_density = 800.0;     ///< kg / m^3, hand links' mass from their shapes
  double revolute_armature = 0.0;  ///< kg m^2, reflected rotor inertia of revolute joints
  /// Parallel jaws (prismatic joints, outside DexGraspBench): the force each jaw presses with,
  /// N (Franka Hand: 70 N continuous; Robotiq 2F-85: 20 to 235 N).
  double jaw_force = 70.0;
  double kp_prismatic = 20000.0;  ///< N / m, position gain of prismatic joints
  /// A gripper whose only actuated joint is revolute (a Robotiq 2F-85's linkage) is a parallel
  /// jaw too: its drive presses each finger's tip with jaw_force (force limit jaw_force x the
  /// tips' summed closing speed per radian, gain kp_prismatic x their squares; at the middle of
  /// the joint's range). false: kp_revolute, as for dexterous hands (DexGraspBench).
  bool revolute_gripper_force = true;
  /// With revolute_gripper_force, the gripper's linkage as the field's MuJoCo model of the
  /// Robotiq 2F-85 builds it (MuJoCo Menagerie: armature on the driver, stiff linkage
  /// constraints): the jaws' damping and armature (prismatic_damping, prismatic_armature) mapped
  /// through the tips' squared speeds and added to the actuated joint (its drive train), the
  /// mimic constraints as stiff as MuJoCo allows (time constant 2 x timestep; impedance 0.95
  /// 0.99 0.001), and its finger links' boxes and cylinders touching with contact patches as
  /// jaw pads do (contact_patch). Without them a light linkage chatters and its pads turn under
  /// a push (test ClosingCheck.ARevoluteGripperPressesWithTheJawForce). false: labels made
  /// before 2026-11-27.
  bool revolute_gripper_linkage = true;
  double prismatic_damping = 100.0;  ///< N s / m, damping of prismatic joints
  /// kg, reflected inertia of a jaw's drive (keeps light jaws stable against stiff contacts).
  double prismatic_armature = 0.1;
  double pregrasp_fraction = 0.9;  ///< pregrasp joints: this far from preshape to the grasp
  double squeeze_fraction = 1.1;   ///< squeeze target: this far from preshape past the grasp
  /// Jaws closed from open (grasps given as a pose alone, whose joint values are where parallel
  /// jaws touch when they close from open at that pose: imported ACRONYM grasps,
  /// docs/ACRONYM.md): the pregrasp is the hand's open preshape, not pregrasp_fraction of the
  /// way, and the squeeze target of each closing joint is its closed limit, so that the
  /// force-limited jaws press with jaw_force as a gripper's grasp command does (a position
  /// drive stops short of it when the target is squeeze_fraction past a touching jaw); the
  /// targets move every step, not every stage (a stage's jump kicks an off-centre object, which
  /// one jaw touches first, out of the jaws). false:
  /// the protocol's pregrasp and squeeze. validateMap sets it for maps that ask for it
  /// (mapClosesFromOpen, validate_map.hpp).
  bool close_from_open = false;
  int interpolation_stages = 10;             ///< control targets per closing phase (linear steps)
  int steps_per_stage = 10;                  ///< simulation steps per control target
  double push_per_mass = 10.0;               ///< N / kg: push force = this x object_mass
  double push_duration = 2.0;                ///< s per direction
  int check_every = 50;                      ///< steps between displacement checks during a push
  double max_translation = 0.05;             ///< m: the grasp fails when the object moves this far
  double max_rotation = 0.2617993877991494;  ///< rad (15 deg): or turns this far
  double max_penetration = 0.01;             ///< m: a hand starting deeper inside the object fails
  /// Contact patches of parallel jaws: MuJoCo 2.2.2 gives one contact point per pair of geoms,
  /// so a jaw pad pressed flat on a face touches at one point and resists twisting only by
  /// torsional friction. With a size > 0, the boxes of links moved by prismatic joints are split
  /// across their two largest extents into cells of about this size (metres, at most 4 per
  /// axis) and their cylinders into segments, each its own geom: the same solid, touching at
  /// several points. Links of revolute fingers keep their shapes (as in DexGraspBench). 0: off.
  double contact_patch = 0.01;
  /// Convex pieces of a non-convex object (MuJoCo collides each mesh geom as its hull).
  int object_max_pieces = 64;
  /// Faces the object mesh is simplified to before its convex decomposition, in [50, 5000]
  /// (ConvexPiecesOptions::max_faces); a second decomposition varies it (robust_hold.hpp).
  int object_max_faces = 600;
  /// The robustness margin (0: off, the protocol as published): under a push the object must
  /// stay within this distance of where the closing left it (its closed state), metres, or the
  /// grasp fails (HoldResult::margin_exceeded). The robust test sets it (robust_hold.hpp).
  double margin_translation = 0.0;
  /// The margin's rotation: under a push the object turns less than this from its closed state,
  /// radians (0: off).
  double margin_rotation = 0.0;
  /// Stop a push once it has settled (docs/VALIDATION.md, "Settled pushes"): the push ends held
  /// after two windows in a row in which the object's drift did not grow (at rest: windows of
  /// settle_window steps, every hand joint slower than settle_joint_speed) or grew steadily
  /// (jitter and creep: windows of check_every steps, no faster than 1.5 times its mean) and
  /// twice that drift over every remaining window keeps it inside every threshold and the settle
  /// envelope. The verdicts are the protocol's checks, every check_every steps. false: every
  /// push runs push_duration (`--full`, the protocol as published).
  bool settle_stop = true;
  int settle_window = 10;  ///< steps between the drift measurements of settle_stop (>= 1)
  /// settle_stop ends a push only while every hand joint is slower than this, rad/s (a slide's
  /// m/s times 10): a hand still moving has not settled.
  double settle_joint_speed = 0.01;
  /// settle_stop ends a push only while the object stays, extrapolated, within this fraction of
  /// the protocol's thresholds from its closed state (or within the margin, when smaller): an
  /// object that slid or turned far has not settled (0, 1].
  double settle_envelope = 0.2;
  /// Use the dynamics the hand's model states (an MJCF hand: masses and inertias, joint damping,
  /// armature and friction loss, servo gains and ranges, geom friction and contact softness;
  /// HandModel::dynamics()) in place of the values above, where it states them
  /// (docs/VALIDATION.md, "A hand's own dynamics"). false: the protocol's values for every hand.
  /// A URDF hand states none: no difference.
  bool stated_dynamics = true;
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
};

/// Why a grasp does or does not hold.
enum class HoldStatus : std::uint8_t {
  kHolds = 0,      ///< the object stayed within the thresholds under all six pushes
  kPenetration,    ///< the hand starts more than max_penetration inside the object
  kLostInClosing,  ///< the object left the thresholds while the hand closed (before a push)
  kSlipped,        ///< the object left the thresholds under a push
  kUnstable,       ///< the simulation diverged (non-finite state or MuJoCo warning)
};

/// Name of an integrator: "implicitfast" or "implicit" (what /validation records).
const char* integratorName(HoldTestOptions::Integrator integrator);

/// The integrator named "implicitfast" or "implicit"; throws Error naming the choices otherwise.
HoldTestOptions::Integrator integratorFromName(const std::string& name);

/// Every integrator's name, the default ("implicit") first: the choices of the CLI options.
std::vector<std::string> integratorNames();

/// Name of a status: "holds", "penetration", "lost_in_closing", "slipped", "unstable".
const char* holdStatusName(HoldStatus status);

/// Names of the push directions in test order: "-x", "+x", "-y", "+y", "-z", "+z" (object frame).
const std::array<const char*, 6>& pushDirectionNames();

/// The physics engine and its version, e.g. "MuJoCo 2.2.2".
std::string physicsEngine();

/// Outcome of one grasp.
struct HoldResult {
  HoldStatus status = HoldStatus::kUnstable;  ///< see HoldStatus
  bool holds = false;                         ///< status == kHolds
  /// Largest displacement of the object from its start over the pushes simulated, metres.
  double max_translation = 0.0;
  /// Largest rotation of the object from its start over the pushes simulated, radians.
  double max_rotation = 0.0;
  /// Largest displacement of the object from its closed state (after the squeeze) under the
  /// pushes simulated, metres: what HoldTestOptions::margin_translation bounds.
  double push_translation = 0.0;
  /// Largest rotation of the object from its closed state under the pushes simulated, radians.
  double push_rotation = 0.0;
  /// The object stayed within the protocol's thresholds but left the margin under a push
  /// (status kSlipped); false without a margin.
  bool margin_exceeded = false;
  /// Index into pushDirectionNames() of the push under which the grasp failed; -1 when it
  /// holds or failed before any push (penetration).
  int failed_direction = -1;
  double initial_penetration = 0.0;  ///< deepest hand-object penetration at the start, metres
  int steps = 0;                     ///< simulation steps taken
};

/// The force one hand link presses on the object at a traced instant.
struct HoldTraceContact {
  int link = -1;       ///< index into HandModel::links()
  double force = 0.0;  ///< summed normal force of its contacts with the object, N
};

/// The object and its contacts at one instant of a traced hold test (HoldTester::trace).
struct HoldTraceSample {
  /// "closing" (pregrasp to grasp), "squeeze" (grasp to squeeze target), or the name of the
  /// push under way (pushDirectionNames(); each push starts again from the squeezed state).
  std::string phase;
  int step = 0;              ///< simulation steps of this test so far
  double translation = 0.0;  ///< object's displacement from its start, metres
  double rotation = 0.0;     ///< object's rotation from its start, radians
  /// The displacement in the palm frame (the hand's base is fixed there), metres.
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  std::vector<HoldTraceContact> contacts;  ///< hand links touching the object, by link index
};

/// A hold test with the object's path: the result test() returns and a sample after each
/// closing stage and each displacement check of the pushes.
struct HoldTrace {
  HoldResult result;                     ///< the same as HoldTester::test's
  std::vector<HoldTraceSample> samples;  ///< in simulation order
};

/// Summary of the simulation model built for a hand and an object.
struct HoldModelInfo {
  int object_pieces = 0;             ///< convex pieces of the object
  double object_volume_error = 0.0;  ///< (pieces - mesh) / mesh volume of the object
  bool object_decomposed = false;    ///< the object was decomposed (not its hull)
  std::string object_note;           ///< why the hull was kept, or ""
  /// The pieces came from the process's cache (same mesh content and options seen before).
  bool object_pieces_cached = false;
  int hand_bodies = 0;        ///< bodies of the hand
  int hand_geoms = 0;         ///< collision geoms of the hand
  int actuators = 0;          ///< position actuators (one per actuated joint)
  int mimic_constraints = 0;  ///< joint equality constraints (URDF mimic)
  /// N m: the force limit of a revolute gripper's drive (HoldTestOptions::revolute_gripper_force),
  /// 0 for other hands.
  double gripper_torque = 0.0;
  /// JSON: which dynamics the hand's model states and the model used (per quantity, how many
  /// the hand's model gave, of how many; docs/VALIDATION.md, "A hand's own dynamics"); "" for a
  /// hand whose model states none (a URDF).
  std::string hand_dynamics;
};

/// What HoldTesterInfo::hand_dynamics records for `hand` under `options` (JSON), without
/// building a model: "" for a hand whose model states no dynamics (a URDF).
std::string handDynamicsJson(const HandModel& hand, const HoldTestOptions& options);

/// Runs the hold test for one hand and one object. Builds the MuJoCo model once (MJCF text
/// from the hand model and the object's convex pieces); test() is const and thread-safe (each
/// call has its own simulation state), and its result depends on its arguments only.
class HoldTester {
 public:
  /// @param hand the hand (URDF + sidecar); @param object the solid (metres, object frame; its
  /// centre of mass and inertia shape the free body). Throws Error when the options are invalid
  /// or MuJoCo refuses the model (with its message).
  HoldTester(const HandModel& hand, const ObjectModel& object, const HoldTestOptions& options = {});
  ~HoldTester();
  HoldTester(HoldTester&&) noexcept;
  HoldTester& operator=(HoldTester&&) noexcept;

  /// Tests the grasp: palm frame `palm` in the object frame, actuated joints `joints`
  /// (HandModel::jointNames() order, radians or metres). Throws Error on a size mismatch.
  HoldResult test(const Pose& palm, const Eigen::VectorXd& joints) const;
  /// test() with the object's path recorded (HoldTrace): where the object goes and which links
  /// press it, to see why a grasp fails. The same simulation: trace(p, q).result == test(p, q).
  HoldTrace trace(const Pose& palm, const Eigen::VectorXd& joints) const;

  /// What the model holds.
  const HoldModelInfo& info() const;
  /// The MJCF text of the model (for inspection: load it in MuJoCo's viewer).
  const std::string& mjcf() const;
  /// The options in force.
  const HoldTestOptions& options() const;

  struct Impl;  ///< private (MuJoCo model)

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace taskmap
