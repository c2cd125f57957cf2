#pragma once
/// @file grasp_simulator.hpp
/// One grasp trial (docs/METHOD.md §2 steps 1-4): put the hand's palm frame at a pose in
/// the object frame with the open preshape, retract it along the approach axis out of the
/// object, close the fingers (autoGrasp), squeeze, and report the contacts. Collision
/// detection is Bullet (float64), kept private.
///
/// Retraction semantics: with a = the approach axis in the object frame, the hand is moved to
/// p(s) = p0 - s a for the smallest s >= 0 at which no link penetrates the object (first exit
/// along the retraction; coarse steps bounded by half the thinnest link or by the current
/// penetration depth, whichever is larger, then bisection until the closest link is within
/// contact_tolerance of the surface). If the hand still penetrates at s = max_retraction the
/// trial is kNotRetractable. If the hand does not penetrate at s = 0 it is advanced along +a
/// (conservative advancement) until it touches; if it touches nothing within max_retraction the
/// trial is kNoPalmContact. When the touching links at the exit do not include the palm (or a
/// link fixed to it) the trial is kNoPalmContact (unless require_palm_contact is false). The
/// palm is then pressed into the surface by the squeeze distance along +a for the closing and
/// the contacts; the reported pose is the pressed one moved back by the squeeze, the palm
/// touching the surface (a palm stored 1 mm inside the object kicks it away in physics,
/// docs/VALIDATION.md).
///
/// Fingertip grasps (GraspMode::kFingertip, from the options or the hand sidecar): the palm is
/// neither required nor pressed. From the exit pose (the first contact coming from outside)
/// the hand backs off along -a until the palm is the standoff from the object (if it is
/// closer); a finger touching first keeps the exit pose. Then the fingers close.
///
/// Closing (GraspIt!'s autoGrasp): every closing joint moves toward its closed limit at its
/// relative speed; coarse steps move no point of the hand by more than half the thinnest moving
/// link, a step that ends in penetration is bisected until the touching link is within
/// contact_tolerance; a link touching the object (or another hand link it can collide with)
/// stops every joint that moves it, distal joints keep closing; joints stop at their limits.
///
/// Coupled jaws (docs/METHOD.md "Coupled jaws"): a mechanism is a closing joint whose links lie
/// on two or more fingers (a URDF <mimic> jaw pair) or a sidecar "coupled" group whose links
/// do. When one of its jaws touches, it does not stop: the palm translates across the
/// approach axis with v = -(I - a a^T) sum_c dir_c speed_c dp/dq_c (p the contact point on the
/// touching jaw), which holds that jaw in place while the others close, until a link of
/// another finger of the mechanism touches (then every touching jaw is squeezed), the joints
/// reach their limits, or a link that does not close (palm, stopped finger) is pressed against a
/// face ahead of the shift (outward normal more than 60 degrees against it), which jams the
/// mechanism with one jaw. The final pose is the shifted one (GraspStats::centring_shift).
/// Squeeze: each joint stopped by an object contact is advanced so that its contact point is
/// pressed the squeeze distance into the object (first order, proximal joints first, a distal
/// joint adding only what its ancestors did not press); when that presses some link of a
/// squeezed chain deeper than twice the squeeze plus the tolerance, the whole squeeze is scaled
/// back (bisection) to that bound.
///
/// Contacts: every triangle a link penetrates after the squeeze (depth > 0) whose outward normal
/// is within 60 degrees of the separation direction (a side face under a palm lying on the top
/// face is no contact), merged per link within 1 mm keeping the deepest; point on the object
/// surface, the triangle's outward normal, depth = the EPA penetration depth.

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/core/contact.hpp"
#include "taskmap/core/pose.hpp"
#include "taskmap/core/triangle_mesh.hpp"
#include "taskmap/grasp_sim/diagnostics.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {

/// Outcome of one trial.
enum class GraspStatus {
  kOk,               ///< hand closed on the object, at least one finger in pressed contact
  kNotRetractable,   ///< the hand still penetrates after retracting max_retraction
  kNoPalmContact,    ///< the palm does not touch the surface when the hand leaves the object
  kNoFingerContact,  ///< every closing joint reached its limit without a finger contact
  kSelfCollision,    ///< two hand links penetrate each other in the final state
  kStepLimit,        ///< closing did not settle within max_closing_steps (degenerate geometry)
};

/// Stable lowercase name: "ok", "not_retractable", "no_palm_contact", "no_finger_contact",
/// "self_collision", "step_limit".
const char* toString(GraspStatus s);
/// Every value, in enum order.
const std::vector<GraspStatus>& allGraspStatuses();

/// Knobs of the simulation.
struct GraspSimOptions {
  double contact_tolerance = 5e-4;  ///< metres; a link within this distance of the surface touches
  /// Longest retraction along -approach, metres; 0 = automatic (enough to clear the object's
  /// bounding sphere from the initial pose: |p0 - c| + r_object + reach + 1 cm).
  double max_retraction = 0.0;
  /// Squeeze distance, metres; negative = the hand sidecar's value.
  double squeeze = -1.0;
  /// When false, a hand whose fingers touch first still closes (finger-first contact).
  /// Palm grasps only (fingertip grasps never require the palm).
  bool require_palm_contact = true;
  /// Palm or fingertip grasps; empty = the hand sidecar's "grasp.mode" (HandModel::graspMode).
  std::optional<GraspMode> grasp_mode;
  /// Fingertip grasps: palm-to-object distance at which the approach stops, metres; negative =
  /// the hand sidecar's "grasp.standoff", else the default of resolveStandoff.
  double standoff = -1.0;
  /// Coupled closing (a closing joint whose links lie on two or more fingers, through URDF
  /// <mimic>, or a sidecar "coupled" group): when one jaw touches, the hand shifts along the
  /// closing direction until another finger of the mechanism touches. False: no centring; a
  /// <mimic> pair stops at the first touch (one-jaw grasps, the behaviour before coupling was
  /// modelled) and the joints of a sidecar group close independently.
  bool centre_coupled = true;
  /// Self-collision: hand links that touch each other while closing stop like object contacts,
  /// and a final state with links penetrating each other is kSelfCollision. Pairs fixed to the
  /// palm together, parent/child pairs and pairs already touching in the preshape are exempt.
  bool check_self_collision = true;
  /// Upper bound on closing steps (coarse steps plus bisections) per trial.
  int max_closing_steps = 4000;
  /// Contact manifold size: at most this many contacts per link (0 = every pressed triangle).
  /// Like Bullet's persistent manifold (4 points), the deepest contact is kept, then the ones
  /// that span the largest patch (farthest point, largest triangle, then the point farthest
  /// from those three). A link pressed into a finely tessellated curve otherwise yields one
  /// contact per triangle (dozens), which adds nothing to the grasp but makes the 6-D wrench
  /// hull of the quality stage cost seconds.
  int max_contacts_per_link = 4;
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
};

/// Counters of one trial (deterministic except the seconds, which need
/// GraspSimDiagnostics::profile).
struct GraspStats {
  int queries = 0;          ///< link-versus-object collision queries
  int closing_steps = 0;    ///< coarse closing steps and bisection evaluations
  double retraction = 0.0;  ///< distance moved along -approach, metres (negative: advanced)
  double standoff = 0.0;    ///< fingertip grasps: extra distance backed off, metres
  /// Fingertip grasps: distance of the palm (and links fixed to it) to the object at the final
  /// pose, metres, +infinity beyond 0.1 m (negative: penetrating); NaN for palm grasps and
  /// trials that end before contacts are collected.
  double palm_gap = std::numeric_limits<double>::quiet_NaN();
  double centring_shift = 0.0;    ///< coupled closing: distance the palm shifted, metres
  double retract_seconds = 0.0;   ///< wall time of the retraction (profile only)
  double close_seconds = 0.0;     ///< wall time of closing and squeeze (profile only)
  double contacts_seconds = 0.0;  ///< wall time of contact extraction (profile only)
};

/// Result of one trial.
struct GraspResult {
  GraspStatus status = GraspStatus::kNoFingerContact;  ///< outcome
  std::string message;                                 ///< human-readable detail
  Pose pose;  ///< final palm pose in the object frame (palm grasps: touching, the squeeze undone)
  Eigen::VectorXd joints;         ///< final values, HandModel::jointNames() order
  std::vector<Contact> contacts;  ///< pressed contacts; link indexes HandModel::links()
  std::vector<std::string> fingers_in_contact;  ///< HandModel::fingerNames() with a contact
  bool palm_contact = false;                    ///< a palm (or palm-fixed) link has a contact
  GraspStats stats;                             ///< counters and timing
};

/// Share of the palm-to-fingertip length (HandModel::rotationScale) that a fingertip grasp
/// keeps between the palm and the object when neither the options nor the sidecar set a
/// standoff (resolveStandoff).
constexpr double kDefaultStandoffShare = 0.1;

/// Standoff in force for fingertip grasps, metres: options.standoff when >= 0, else the
/// sidecar's "grasp.standoff" when it sets one, else max(kDefaultStandoffShare x the hand's
/// palm-to-fingertip length, 4 x options.contact_tolerance): a tenth of the fingers' reach
/// keeps the palm off the object (issue 30: with 0, the approach stopped on the palm) and
/// leaves nine tenths of the fingers to reach it. Throws Error for invalid options.
double resolveStandoff(const HandModel& hand, const GraspSimOptions& options);

/// What GraspSimulator::simulate computes of a trial that fails.
enum class FailureDetail {
  /// The trial runs to where it fails: pose, joints, contacts, stats and message are those.
  kFull,
  /// The trial may end as soon as its status is certain (what a build keeps of a failed
  /// trial): the status is kFull's, bit for bit; pose, joints, contacts and stats are where it
  /// ended. Ends early: no_palm_contact once the palm, moving on out of the object, provably
  /// stays beyond the contact tolerance (CollisionScene::linkSweepClear; palm grasps that
  /// require the palm, automatic max_retraction); step_limit without contacts;
  /// self_collision before the contacts. Successful trials are kFull's.
  kStatus,
};

/// Simulates grasp trials of one hand on one object. Construction builds the object's
/// bounding-volume hierarchy once; simulate() is const, thread-safe and lock-free (each thread
/// lazily gets its own Bullet dispatcher), and deterministic.
class GraspSimulator {
 public:
  /// @param object the object (its mesh is copied). @param hand the hand (copied).
  /// @param diagnostics baseline paths and profiling for tests and benchmarks.
  GraspSimulator(const ObjectModel& object, const HandModel& hand,
                 const GraspSimOptions& options = {}, const GraspSimDiagnostics& diagnostics = {});
  /// Same for a raw closed, outward-oriented mesh in metres (object frame = mesh coordinates).
  GraspSimulator(const TriangleMesh& mesh, const HandModel& hand,
                 const GraspSimOptions& options = {}, const GraspSimDiagnostics& diagnostics = {});
  ~GraspSimulator();
  GraspSimulator(const GraspSimulator&) = delete;
  GraspSimulator& operator=(const GraspSimulator&) = delete;

  /// Runs one trial from the initial palm pose (object frame). Thread-safe, deterministic.
  GraspResult simulate(const Pose& initial_palm_pose) const;
  /// The same trial; with FailureDetail::kStatus a failed trial may end early (same status).
  GraspResult simulate(const Pose& initial_palm_pose, FailureDetail detail) const;
  /// The hand simulated.
  const HandModel& hand() const;
  /// The options in force.
  const GraspSimOptions& options() const;
  /// The diagnostics switches in force.
  const GraspSimDiagnostics& diagnostics() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;  // Bullet stays hidden
};

}  // namespace taskmap
