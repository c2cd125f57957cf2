#pragma once
/// @file size_check.hpp
/// Is an object's size plausible for a hand? A build refuses an object whose largest side is
/// more than kMaxReachRatio times the open hand's reach (a file in millimetres, centimetres or
/// inches read as metres) or smaller than the hand's thinnest finger link (a metre file scaled
/// down), in well under a second, with the measured sizes and the scale that would fix it.
/// BuildOptions::check_size = false (`--allow-size`) builds it anyway.

#include <functional>
#include <string>

#include <Eigen/Core>

#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {

/// Largest object side, in multiples of the hand's reach, a size check accepts.
constexpr double kMaxReachRatio = 20.0;
/// Objects larger than this many times the reach "dwarf" the hand: a build of such an object
/// that stores no grasp names the size first among the suspects.
constexpr double kDwarfReachRatio = 5.0;

/// Thickness (smallest extent) of the hand's thinnest finger link, metres: for each finger link
/// with geometry the largest CollisionShape::thickness() of its shapes, the smallest over the
/// links; 0 when no finger link has geometry.
double thinnestFingerLink(const HandModel& hand);

/// The sizes a size check compares.
struct ObjectSizeCheck {
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  ///< bounding-box sides, metres
  double extent = 0.0;                             ///< largest side, metres
  double reach = 0.0;                              ///< HandModel::reach(), metres
  double finger = 0.0;                             ///< thinnestFingerLink(), metres
  bool too_large = false;                          ///< extent > kMaxReachRatio * reach
  bool too_small = false;                          ///< extent < finger
  /// "" when plausible; else one message: the sizes measured, the limit, and the scale
  /// (`--scale`) that makes the object plausible if its file is in other units.
  std::string problem;
  /// The object's size against the hand and the scale advice, in one sentence (also when
  /// plausible), e.g. "the object is 19 m across, 105 times the 0.18 m reach of hand ...".
  std::string sizes;
};

/// Measures the object against the hand (no simulation: microseconds).
ObjectSizeCheck checkObjectSize(const ObjectModel& object, const HandModel& hand);

/// The same from an object's bounding-box sides (metres), the scale it was loaded with and its
/// name: for a check while the mesh loads (sizeCheckOnLoad).
ObjectSizeCheck checkObjectSize(const Eigen::Vector3d& size, double scale, const std::string& name,
                                const HandModel& hand);

/// Throws Error with checkObjectSize's problem (and how to build anyway) when it has one.
/// buildMap and TrialRunner call it unless BuildOptions::check_size is false.
void requirePlausibleSize(const ObjectModel& object, const HandModel& hand);

/// A check for ScopedLoadBoundsCheck (object_size.hpp) that throws requirePlausibleSize's error
/// for an object named `name` (its file stem) and `hand` (which must outlive the check), given
/// the load's scale: the refusal then comes right after the mesh is read, before its repair.
std::function<void(const Eigen::Vector3d&)> sizeCheckOnLoad(const HandModel& hand,
                                                            const std::string& name, double scale);

}  // namespace taskmap
