#pragma once
/// @file palm_enclose.hpp
/// Palm-first enclosing poses for multi-finger hands (SamplerKind::kPalmEnclose, docs/METHOD.md
/// §2 "Palm on the surface, fingers across the narrow extent"): the palm's front flat on a
/// surface point, the fingers' closing axis turned across the object's narrowest local extent,
/// the open fingers checked outside the object before any simulation.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "taskmap/core/pose.hpp"
#include "taskmap/core/random.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {

/// Where a multi-finger hand's palm and fingers are, palm frame, open preshape, from its
/// collision shapes (encloseGeometry()). Coordinates "across" are along the closing axis c and
/// along v = c x a (a: the approach axis).
struct EncloseGeometry {
  /// Unit, palm frame, perpendicular to the approach axis: the principal direction of the
  /// fingers' motion across the approach when they close (preshape to closing targets).
  Eigen::Vector3d closing_axis = Eigen::Vector3d::UnitX();
  /// Metres along the approach axis: the front-most point of the palm-rigid links' shapes.
  double palm_front = 0.0;
  /// Metres ahead of palm_front: depth at which the object's extent across c is measured
  /// (the closed fingers' centroid, at least 5 mm).
  double probe_depth = 0.005;
  /// Metres along c: the open fingers' points' smallest and largest coordinates.
  double span_min = 0.0;
  double span_max = 0.0;  ///< see span_min, metres, > span_min
  /// Metres, (along c, along v): where the object's extent across c is centred (the closed
  /// fingers' centroid along c, the palm's centre along v).
  Eigen::Vector2d grasp_centre = Eigen::Vector2d::Zero();
  /// Metres, (along c, along v): the palm-rigid links' points' smallest and largest coordinates.
  Eigen::Vector2d palm_min = Eigen::Vector2d::Zero();
  Eigen::Vector2d palm_max = Eigen::Vector2d::Zero();  ///< see palm_min, metres
  /// Metres, >= 0: how far the object must reach ahead of the palm's front (along the approach)
  /// where the fingers close, or the fingers fold over it onto the palm (`self_collision`):
  /// half the thinnest finger link's thickness (encloseGeometry). 0: no such test.
  double min_depth = 0.0;
  /// Throws Error naming the field when a value is out of range.
  void validate() const;
};

/// The geometry of a hand with at least two fingers whose closing moves them across the
/// approach axis; empty for other hands (no finger shapes, no closing motion across a).
std::optional<EncloseGeometry> encloseGeometry(const HandModel& hand);

/// One draw of the palm-enclose sampler from `rng`: up to `attempts` surface points q (each
/// with a roll psi, drawn whether accepted or not), each tried with the closing axis along the
/// kRolls directions psi + k pi / kRolls across -n(q), narrowest object extent first. A
/// direction is accepted when the object's extent across it at the probe depth (its outermost
/// surface crossings, through hollows: a mug's far wall, not its wall) fits the open fingers'
/// span (with `margin`, metres, each side), the object reaches at least geometry.min_depth ahead
/// of the palm's front at q or at the midpoint of the chord's first crossings (deepEnough), the
/// palm's face is clear (rays to its edges and
/// corners) and no point of `finger_points` (palm frame, metres; fingerCheckPoints) lies inside
/// the object or within 0.5 mm of its surface. Returns the palm pose (palm frame in the object
/// frame), or empty when every attempt failed.
std::optional<Pose> drawPalmEnclose(const ObjectModel& object, const EncloseGeometry& geometry,
                                    const Eigen::Vector3d& approach_axis,
                                    const std::vector<Eigen::Vector3d>& finger_points, int attempts,
                                    double margin, Rng& rng);

/// The same points in coarse-to-fine order for inside tests: index 0, then the indices that are
/// multiples of the largest power of two, then of the next smaller one, ..., the odd indices
/// last (each group in input order). An all-points test gives the same answer in any order; a
/// pose whose fingers overlap the object is rejected after a few tests wherever the overlap is,
/// not only when it is at the front of the list (fingerCheckPoints puts the fingertips first:
/// the Allegro's flat fingers came after its thumb's points).
std::vector<Eigen::Vector3d> coarseToFine(const std::vector<Eigen::Vector3d>& points);

/// Closing-axis directions tried per surface point by drawPalmEnclose.
inline constexpr int kEncloseRolls = 8;

}  // namespace taskmap
