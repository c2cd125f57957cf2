#pragma once
/// @file qhull_run.hpp
/// One run of reentrant qhull (libqhull_r, kept private to meshes) on a point set of any
/// dimension, answered in Eigen values: the one place that sets qhull up, for the 3-D hulls of
/// hand collision meshes and the 6-D wrench hulls of the quality stage. Thread-safe: every call
/// owns its qhull instance; qhull never prints.

#include <string>
#include <vector>

#include <Eigen/Core>

namespace taskmap {

/// What a qhull run produced.
struct QhullOutput {
  int exit_code = 0;          ///< qhull's exit code, 0 on success
  bool singular = false;      ///< true when qhull found the input flat (initial simplex singular)
  std::string error;          ///< qhull's meaning of a non-zero exit code, empty on success
  Eigen::MatrixXd normals;    ///< dim x facets: outward unit facet normals (when asked for)
  Eigen::VectorXd offsets;    ///< facets: normal . x + offset = 0 on the facet (when asked for)
  std::vector<int> vertices;  ///< indices into the input of the hull's vertices (qhull order)
  double volume = 0.0;        ///< hull volume (qhull flag "FA"), 0 when not computed
};

/// Runs qhull with `flags` (qhull options after "qhull", e.g. "Qt FA") on the points stored one
/// after another in `coords` (size: dim * point count), dim in [2, 9]. `facets` and `vertices`
/// choose which parts of the hull to copy out. Never throws for qhull failures: they come back
/// as exit_code / error. Throws Error on a coordinate count that is not a multiple of dim.
QhullOutput runQhull(int dim, const std::vector<double>& coords, const std::string& flags,
                     bool facets, bool vertices);

}  // namespace taskmap
