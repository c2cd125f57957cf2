// The mass model of a hand link (link_inertia.hpp).
#include "taskmap/hands/link_inertia.hpp"

#include <algorithm>

#include <Eigen/Geometry>

#include "taskmap/core/constants.hpp"

namespace taskmap {

double shapeVolume(const CollisionShape& s) {
  switch (s.type) {
    case ShapeType::kBox:
      return s.box_size.prod();
    case ShapeType::kCylinder:
      return kPi * s.radius * s.radius * s.length;
    case ShapeType::kSphere:
      return 4.0 / 3.0 * kPi * s.radius * s.radius * s.radius;
    case ShapeType::kConvex: {
      Eigen::AlignedBox3d box;
      for (const auto& p : s.points) box.extend(p);
      return s.points.empty() ? 0.0 : 0.5 * box.sizes().prod();
    }
  }
  return 0.0;
}

LinkInertia linkInertia(const HandLink& link, double density) {
  double volume = 0.0;
  LinkInertia r;
  for (const auto& s : link.shapes) {
    const double v = shapeVolume(s);
    volume += v;
    r.centre += v * s.origin.translation();
  }
  if (volume > 0.0) r.centre /= volume;
  double radius = 0.0;
  for (const auto& s : link.shapes)
    radius = std::max(radius, (s.origin.translation() - r.centre).norm() + s.boundingRadius());
  r.mass = std::max(density * volume, 1e-3);
  r.inertia = std::max(0.4 * r.mass * radius * radius, 1e-8);
  return r;
}

}  // namespace taskmap
