// The object's size against the hand's (size_check.hpp).
#include "taskmap/builder/size_check.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "taskmap/core/error.hpp"
#include "taskmap/core/text.hpp"
#include "taskmap/meshes/object_size.hpp"

namespace taskmap {
namespace {}  // namespace

double thinnestFingerLink(const HandModel& hand) {
  double thinnest = std::numeric_limits<double>::infinity();
  for (const HandLink& link : hand.links()) {
    if (link.finger < 0 || link.shapes.empty()) continue;
    double thickness = 0.0;
    for (const CollisionShape& s : link.shapes) thickness = std::max(thickness, s.thickness());
    thinnest = std::min(thinnest, thickness);
  }
  return std::isfinite(thinnest) ? thinnest : 0.0;
}

ObjectSizeCheck checkObjectSize(const Eigen::Vector3d& size, double scale, const std::string& name,
                                const HandModel& hand) {
  ObjectSizeCheck c;
  c.size = size;
  c.extent = c.size.maxCoeff();
  c.reach = hand.reach();
  c.finger = thinnestFingerLink(hand);
  if (!(c.reach > 0)) return c;
  c.too_large = c.extent > kMaxReachRatio * c.reach;
  c.too_small = c.extent < c.finger;
  const double ratio = c.extent / c.reach;
  const std::string ratio_text = ratio >= 1.5   ? shortNumber(ratio) + " times"
                                 : ratio >= 0.5 ? "about"
                                                : "1/" + shortNumber(1.0 / ratio) + " of";
  const double lo = std::max(c.finger, kGraspableMinExtent);
  const double hi = kMaxReachRatio * c.reach;
  c.sizes = "the object is " + shortNumber(c.extent) + " m across (bounding box " +
            shortNumber(c.size.x()) + " x " + shortNumber(c.size.y()) + " x " +
            shortNumber(c.size.z()) + " m), " + ratio_text + " the " + shortNumber(c.reach) +
            " m reach of hand '" + hand.name() +
            "' (open, from the palm); its thinnest finger link is " + shortNumber(c.finger) + " m";
  const std::string advice = scaleAdvice(c.extent, scale, lo, hi, c.reach);
  const std::string what = "object '" + name + "' ";
  if (c.too_large)
    c.problem = what + "is too large for the hand: " + c.sizes +
                "; a graspable object is at most " + shortNumber(kMaxReachRatio) +
                " times the reach; " + advice;
  else if (c.too_small)
    c.problem = what + "is too small for the hand: " + c.sizes +
                "; a graspable object is at least as large as the thinnest finger link; " + advice;
  return c;
}

ObjectSizeCheck checkObjectSize(const ObjectModel& object, const HandModel& hand) {
  const MassProperties& mp = object.massProperties();
  return checkObjectSize(mp.bounds_max - mp.bounds_min, object.scale(), object.name(), hand);
}

void requirePlausibleSize(const ObjectModel& object, const HandModel& hand) {
  const ObjectSizeCheck size = checkObjectSize(object, hand);
  if (!size.problem.empty())
    throw Error(size.problem + "; to build it as it is: --allow-size (check_size = false)");
}

std::function<void(const Eigen::Vector3d&)> sizeCheckOnLoad(const HandModel& hand,
                                                            const std::string& name, double scale) {
  return [&hand, name, scale](const Eigen::Vector3d& size) {
    const ObjectSizeCheck c = checkObjectSize(size, scale, name, hand);
    if (!c.problem.empty())
      throw Error(c.problem + "; to build it as it is: --allow-size (check_size = false)");
  };
}

}  // namespace taskmap
