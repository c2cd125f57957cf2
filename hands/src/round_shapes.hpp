#pragma once
// Private to hands: capsules and ellipsoids (MJCF geoms) as the points of a convex polytope
// inscribed in them (HandModel has no round primitive besides spheres and cylinders; a
// CollisionShape of kind kConvex holds these points). 24 points around, 6 rings from the equator
// to each pole: the polytope lies within 0.9 % of the radius inside the surface.
#include <vector>

#include <Eigen/Core>

namespace taskmap::detail {

/// Points on a capsule of radius r whose straight part has length `length` along z, centred
/// at the origin (metres).
std::vector<Eigen::Vector3d> capsulePoints(double r, double length);

/// Points on an ellipsoid with semi-axes `radii` along x, y, z, centred at the origin (metres).
std::vector<Eigen::Vector3d> ellipsoidPoints(const Eigen::Vector3d& radii);

}  // namespace taskmap::detail
