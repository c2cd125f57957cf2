#pragma once
/// @file convex_hull.hpp
/// Convex hulls of 3-D point sets through reentrant qhull (qhull_run.hpp): the hull of a hand's
/// mesh geom, the pieces of a convex decomposition (convex_pieces.hpp).
#include <string>
#include <vector>

#include <Eigen/Core>

namespace taskmap {

/// A convex hull: its own vertices (a subset of the input, sorted lexicographically) and volume.
struct PointHull {
  std::vector<Eigen::Vector3d> vertices;  ///< metres
  double volume = 0.0;                    ///< m^3
};

/// Convex hull of `points` with qhull ("Qt": triangulated output; no output on stdout or
/// stderr). Throws Error starting with `what` when the points are fewer than 4 or flat.
PointHull convexHull(const std::vector<Eigen::Vector3d>& points, const std::string& what);

}  // namespace taskmap
