#pragma once
/// @file sampler.hpp
/// Initial hand poses for grasp trials (docs/METHOD.md §2 step 1). Trial i of a run seeded
/// with s draws only from Rng(s, i), so the set of trials never depends on thread count.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "taskmap/core/pose.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"
#include "taskmap/sampler/palm_enclose.hpp"

namespace taskmap {

/// How the initial palm pose of a trial is drawn.
enum class SamplerKind {
  /// The paper's sampler: palm origin uniform inside the object volume, orientation uniform
  /// on SO(3). The simulator then retracts the hand out of the object.
  kVolume,
  /// Area-weighted surface point, approach axis along the inward normal, uniform roll about
  /// the normal, palm origin at a uniform signed standoff along the outward normal. Finds thin
  /// parts (handles) that volume sampling rarely hits.
  kSurface,
  /// Even trial indices volume, odd trial indices surface.
  kMixed,
  /// Parallel jaws (Dex-Net's antipodal sampler, docs/METHOD.md §2 "Antipodal sampling"): a
  /// surface point p1, a ray into the object from it inside the friction cone about -n1 to
  /// the exit point p2; accepted when both normals lie in the friction cones about the jaw
  /// axis p2 - p1 and |p2 - p1| fits the jaws' opening. The jaws close along p2 - p1, the
  /// approach is uniform about that axis, the pads' midpoint at (p1 + p2) / 2. Needs
  /// SamplerOptions::jaws; a trial whose attempts all fail falls back to kSurface.
  kAntipodal,
  /// Multi-finger hands (docs/METHOD.md §2 "Enclosing approach"): as kSurface with the palm
  /// origin on the surface point (no standoff), accepted only when no point of the open
  /// fingers (SamplerOptions::finger_points) lies inside the object, so that the palm, not a
  /// fingertip, meets the surface and the fingers enclose the part. Needs finger_points; a
  /// trial whose attempts all fail falls back to kSurface.
  kEnclose,
  /// Parallel jaws whose palm must touch (docs/METHOD.md §2 "Antipodal pairs with the palm on
  /// the surface"). With SamplerOptions::place_palm: the palm's front flat on an area-weighted
  /// surface point q (approach along -n(q)); the jaws' closing axis turned onto the normal of
  /// the wall a drawn direction meets; accepted when, at the pads' depth (or halfway through the
  /// object when it is thinner), the two surface points across that axis fit the opening with
  /// their normals in the friction cones, no surface crosses the palm's face plane 1 cm behind
  /// q, and no point of the open fingers (SamplerOptions::finger_points) is inside. Without
  /// place_palm (fingertip grasps): kAntipodal's pads on the pair, with the finger check. Needs
  /// jaws and finger_points; a trial whose attempts all fail falls back to kSurface.
  kAntipodalPalm,
  /// Multi-finger palm grasps (docs/METHOD.md §2 "Palm on the surface, fingers across the narrow
  /// extent", palm_enclose.hpp): the palm's front flat on an area-weighted surface point, the
  /// fingers' closing axis across the object's narrowest chord there that fits the open
  /// fingers, the chord centred on where the fingers close; accepted when the palm's face is
  /// clear and no point of the open fingers (finger_points) is inside. Needs
  /// SamplerOptions::enclose and finger_points; all attempts failing falls back to kSurface.
  kPalmEnclose,
};

/// "volume", "surface", "mixed", "antipodal", "enclose", "antipodal_palm", "palm_enclose".
const char* toString(SamplerKind kind);
/// Parses a sampler name; throws Error listing the valid names on an unknown one.
SamplerKind samplerKindFromString(const std::string& name);

/// Where the pads of a parallel-jaw hand are, in the palm frame (jawGeometry()).
struct JawGeometry {
  /// Unit, palm frame, perpendicular to the approach axis: from the first finger's pad toward
  /// the second's.
  Eigen::Vector3d closing_axis = Eigen::Vector3d::UnitX();
  /// Palm frame, metres: midpoint between the two pads' inner faces in the open preshape.
  Eigen::Vector3d pad_midpoint = Eigen::Vector3d::Zero();
  double open_width = 0.0;    ///< metres between the pads' inner faces in the preshape, > 0
  double closed_width = 0.0;  ///< metres between them with the closing joints at their targets
  /// Palm frame, metres along the approach axis: the front-most point of the palm-rigid links'
  /// collision shapes (their points as openFingerPoints takes them); 0 when they have none.
  double palm_front = 0.0;
  /// Palm frame, metres: the palm-rigid links' points' smallest and largest coordinates along
  /// the closing axis (x) and along closing axis x approach axis (y); zero when they have none.
  Eigen::Vector2d palm_min = Eigen::Vector2d::Zero();
  Eigen::Vector2d palm_max = Eigen::Vector2d::Zero();  ///< see palm_min, metres
  /// Throws Error naming the field when a value is out of range.
  void validate() const;
};

/// The pads of a hand with exactly two fingers, from the collision shapes of each finger's
/// distal body (its links with shapes behind the most moving joints: a Robotiq's inner finger
/// and pad, not the knuckles in front of its palm; the whole finger of a one-link jaw): closing
/// axis from the first finger's distal points toward the second's (across the approach axis),
/// each pad the distal points within 2 mm of its inner face (preshape), widths from the inner
/// faces in the preshape and with every closing joint at its target. Empty for other hands
/// (more or fewer fingers, fingers without shapes, pads that do not face each other).
std::optional<JawGeometry> jawGeometry(const HandModel& hand);

/// The sampler of a build that names none: kAntipodalPalm for a parallel-jaw hand (jawGeometry()
/// not empty), kMixed for any other hand (docs/METHOD.md §2; measured in
/// docs/history/performance-2026-11.md, "antipodal_palm, the jaws' default"; builds choose
/// palm_enclose for hands it can place: builder's chooseSampler).
SamplerKind defaultSamplerKind(const HandModel& hand);

/// Points spanning the collision shapes of every finger link in the open preshape, palm frame,
/// metres: box corners, hull points, the extremes of spheres and cylinders along their axes.
std::vector<Eigen::Vector3d> openFingerPoints(const HandModel& hand);

/// Points on the collision shapes of every finger link in the open preshape, palm frame,
/// metres, for inside tests: openFingerPoints, plus points at most `spacing` apart on every
/// box face (a grid) and cylinder side, and the midpoints of hull points closer than 2 spacing.
/// Throws Error unless spacing > 0.
std::vector<Eigen::Vector3d> fingerCheckPoints(const HandModel& hand, double spacing);

/// Points spanning the collision shapes of each finger's links at joint values q (jointNames()
/// order), palm frame, metres, one list per finger (fingerNames() order).
std::vector<std::vector<Eigen::Vector3d>> fingerShapePoints(const HandModel& hand,
                                                            const Eigen::VectorXd& q);
/// Points spanning the collision shapes of the palm-rigid links at q, palm frame, metres.
std::vector<Eigen::Vector3d> palmShapePoints(const HandModel& hand, const Eigen::VectorXd& q);

/// Options of the sampler.
struct SamplerOptions {
  /// The sampler; unset: kAntipodalPalm when `jaws` and `finger_points` are given, kMixed
  /// otherwise (a build gives them for a parallel-jaw hand: defaultSamplerKind()).
  std::optional<SamplerKind> kind;
  /// Unit direction, palm frame, in which the hand moves toward the object
  /// (HandModel::approachAxis()).
  Eigen::Vector3d approach_axis = Eigen::Vector3d::UnitZ();
  /// Surface sampler: signed distance of the palm origin from the surface point along the
  /// outward normal, uniform in [standoff_min, standoff_max], metres. Positive starts the palm
  /// outside (the simulator advances it along the approach axis until it touches), negative
  /// inside (the simulator retracts it out of the object).
  double standoff_min = 0.0;
  double standoff_max = 0.02;  ///< metres, >= standoff_min
  /// Antipodal sampler: the jaws' pads (from jawGeometry of the hand); required by kAntipodal.
  std::optional<JawGeometry> jaws;
  /// Antipodal sampler: Coulomb friction coefficient of the cones (the build's
  /// QualityOptions::friction), >= 0; half-angle atan(friction).
  double friction = 0.5;
  /// Antipodal and enclose samplers: candidates tried per trial before the fallback, >= 1.
  int attempts = 16;
  /// Enclose sampler: points of the open fingers' collision shapes, palm frame, metres
  /// (openFingerPoints of the hand); required by kEnclose.
  std::vector<Eigen::Vector3d> finger_points;
  /// Antipodal sampler: a pair is kept when closed_width + margin <= |p2 - p1| <=
  /// open_width - margin, metres, >= 0.
  double width_margin = 0.002;
  /// kAntipodalPalm: palm grasps, the palm's front placed on the surface (true), or fingertip
  /// grasps, the pads on an antipodal pair (false). The builder sets it from the grasp mode.
  bool place_palm = true;
  /// kPalmEnclose: the hand's palm and fingers (encloseGeometry of the hand); required by it.
  std::optional<EncloseGeometry> enclose;
  /// kPalmEnclose: the object's chord must fit the open fingers' span less this much on each
  /// side, metres, >= 0.
  double enclose_margin = 0.005;
  /// Throws Error naming the option when a value is out of range (non-unit axis, bad range).
  void validate() const;
};

/// The kind `options` samples with: options.kind, or when unset kAntipodalPalm if jaws and
/// finger_points are given, else kMixed.
SamplerKind samplerKindOf(const SamplerOptions& options);

/// An antipodal pair of surface points (object frame).
struct AntipodalPair {
  Eigen::Vector3d p1, n1;  ///< first contact and its outward unit normal
  Eigen::Vector3d p2, n2;  ///< second contact (where the ray leaves) and its outward unit normal
};

/// One antipodal attempt: a surface point from `rng`, a direction uniform in the cone of
/// half-angle atan(friction) about its inward normal, the ray's exit point. Returns the pair when
/// both normals lie in the friction cones about the axis and the width is in [min_width,
/// max_width] (metres); empty otherwise. Draws the same number of values from `rng` either way.
std::optional<AntipodalPair> antipodalAttempt(const ObjectModel& object, Rng& rng, double friction,
                                              double min_width, double max_width);

/// Draws initial palm poses (palm frame in the object frame). Immutable, thread-safe.
class Sampler {
 public:
  /// @param object the solid to sample (copies share state). Throws Error on invalid options,
  /// for kAntipodal without jaws, kEnclose without finger points, kAntipodalPalm without
  /// either and kPalmEnclose without enclose or finger points.
  Sampler(ObjectModel object, const SamplerOptions& options);

  /// Initial pose of trial `trial` of a run seeded with `seed`: a pure function of both.
  Pose sample(std::uint64_t seed, std::uint64_t trial) const;
  /// Antipodal samplers: the pair trial `trial` grasps, empty when it fell back to kSurface (or
  /// the sampler is of another kind). A pure function of seed and trial, as sample().
  std::optional<AntipodalPair> antipodalPair(std::uint64_t seed, std::uint64_t trial) const;
  /// kAntipodalPalm without place_palm: the palm pose that puts the pads on `pair` with the
  /// approach at angle `spin` about it, or empty when a finger point is inside the object.
  std::optional<Pose> palmJawPose(const AntipodalPair& pair, double spin) const;
  /// The concrete kind (kVolume, kSurface, kAntipodal, kEnclose, kAntipodalPalm or
  /// kPalmEnclose) trial `trial` uses (kMixed's, and kAntipodalPalm's and kPalmEnclose's with
  /// attemptsInForce() 0: kVolume on even trials, kSurface on odd).
  SamplerKind kindOfTrial(std::uint64_t trial) const;
  /// The options given at construction.
  const SamplerOptions& options() const { return options_; }
  /// Attempts a trial makes before the surface sampler's pose. options().attempts, except for
  /// kAntipodalPalm and kPalmEnclose on an object where a probe at construction (64 attempts
  /// from generators of their own, the same for any seed and thread) predicts that fewer than
  /// half the trials would find a pose within options().attempts: then 0, the trials being the
  /// mixed sampler's (kindOfTrial: volume on even trials, surface on odd; fall back fast,
  /// docs/METHOD.md §2).
  int attemptsInForce() const { return attempts_; }

 private:
  Pose surfacePose(Rng& rng) const;
  std::optional<AntipodalPair> drawPair(Rng& rng) const;
  std::optional<std::pair<AntipodalPair, Pose>> drawPalmJaw(Rng& rng) const;
  std::optional<std::pair<AntipodalPair, Pose>> palmJawAttempt(Rng& rng, double min_w,
                                                               double max_w) const;
  int probeAttempts() const;
  std::optional<std::pair<AntipodalPair, Pose>> palmFirstAttempt(const SurfaceSample& q,
                                                                 double through, double roll,
                                                                 double min_w, double max_w) const;
  bool fingersOutside(const Pose& palm, double clearance = 0.0) const;
  void groupFingerPoints();  ///< fills finger_groups_ from options_.finger_points
  bool palmFaceClear(const Pose& pose, const Eigen::Vector3d& face) const;
  Pose jawPose(const AntipodalPair& pair, double spin) const;

  ObjectModel object_;
  SamplerOptions options_;
  int attempts_ = 1;  ///< attemptsInForce()
  /// antipodal_palm: the finger points whose distance to the surface is tested, one per
  /// kClearanceCell cube (a Robotiq's 45,652 finger points, mostly hull midpoints, become a few
  /// thousand), in finger_points' order.
  std::vector<Eigen::Vector3d> clearance_points_;
  /// The finger points by 1 cm cube of the palm frame, in finger_points' order of first
  /// appearance, with the centre and radius of a ball holding each cube's points: where that
  /// ball lies outside the object (centre outside, no surface within the radius), none of its
  /// points is inside, and fingersOutside() skips them (the same verdicts; a Robotiq's 45,652
  /// points, mostly hull midpoints, fill a few hundred cubes).
  struct FingerGroup {
    Eigen::Vector3d centre;
    double radius = 0.0;
    std::vector<Eigen::Vector3d> points;
  };
  std::vector<FingerGroup> finger_groups_;
};

/// Orientation whose rotation maps the palm-frame axis onto `direction` (both unit), followed
/// by a rotation of `roll` radians about `direction`.
Eigen::Quaterniond alignAxis(const Eigen::Vector3d& axis, const Eigen::Vector3d& direction,
                             double roll);

}  // namespace taskmap
