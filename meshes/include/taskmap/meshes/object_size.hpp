#pragma once
/// @file object_size.hpp
/// Is an object's size plausible for grasping, and which scale (file units to metres) would
/// make it so: the advice behind the size checks of the loader, `taskmap mesh-info` and the
/// build (builder/size_check.hpp, which knows the hand).

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace taskmap {

/// Largest bounding-box side of a hand-held object, metres, that a size check without a hand
/// accepts without a warning (`mesh-info`): 5 mm to 0.5 m, typically 0.1 m.
constexpr double kGraspableMinExtent = 0.005;
constexpr double kGraspableMaxExtent = 0.5;
constexpr double kGraspableTypicalExtent = 0.1;

/// A unit a mesh file may be written in, and what the object measures if it is.
struct UnitGuess {
  std::string unit;     ///< "metres", "centimetres", "millimetres", "inches"
  double scale = 1.0;   ///< the scale (file units to metres) of that unit
  double extent = 0.0;  ///< the object's largest side at that scale, metres
};

/// The units (metres, centimetres, millimetres, inches) other than `current_scale` under which
/// an object of `file_extent` (largest bounding-box side in file units) measures within
/// [lo, hi] metres, nearest to `typical` (ratio) first.
std::vector<UnitGuess> unitGuesses(double file_extent, double current_scale, double lo, double hi,
                                   double typical);

/// One sentence of advice for an object of `extent` metres loaded with scale `current_scale`
/// whose size is implausible: the scale (`--scale`) that fixes it if its file is in another
/// unit, with the size it would have, e.g. "is the file in centimetres? scale 0.01 (--scale
/// 0.01) makes it 0.19 m across (in millimetres: --scale 0.001, 0.019 m)"; or, when no unit
/// gives a size within [lo, hi], says so.
std::string scaleAdvice(double extent, double current_scale, double lo, double hi, double typical);

/// "" when `extent` (metres) is within [kGraspableMinExtent, kGraspableMaxExtent]; else one
/// sentence saying it is large or small for a graspable object, with scaleAdvice.
std::string graspableSizeWarning(double extent, double current_scale);

/// While alive, every ObjectModel::load and ObjectModel::fromMesh on this thread calls `check`
/// with the bounding-box sides (metres) of the mesh's vertices right after reading them, before
/// the repair and the solid (most of a load's time); `check` may throw to refuse the object
/// early, e.g. a size check that knows the hand (builder/size_check.hpp). Scopes nest (the
/// innermost applies).
class ScopedLoadBoundsCheck {
 public:
  explicit ScopedLoadBoundsCheck(std::function<void(const Eigen::Vector3d& size)> check);
  ~ScopedLoadBoundsCheck();
  ScopedLoadBoundsCheck(const ScopedLoadBoundsCheck&) = delete;
  ScopedLoadBoundsCheck& operator=(const ScopedLoadBoundsCheck&) = delete;

  /// The innermost check of this thread (nullptr when none).
  static const std::function<void(const Eigen::Vector3d&)>* current();

 private:
  std::function<void(const Eigen::Vector3d&)> check_;
  const std::function<void(const Eigen::Vector3d&)>* previous_;
};

}  // namespace taskmap
