#pragma once
/// @file wrench_hull.hpp
/// The convex hull of a 6-D wrench set (reentrant qhull behind the scenes), exposed for tests
/// and tools. evaluateGrasp() uses it. Thread-safe: no global state, no lock.

#include <string>

#include <Eigen/Core>

#include "taskmap/quality/grasp_quality.hpp"

namespace taskmap {

/// 6 x N matrix of wrenches (force; torque / torque scale), one per column.
using WrenchMatrix = Eigen::Matrix<double, 6, Eigen::Dynamic>;

/// Relative thickness below which a wrench set counts as spanning fewer than 6 dimensions:
/// the smallest singular value of the centred wrench matrix divided by the largest.
constexpr double kDegenerateSpread = 1e-7;

/// The origin counts as strictly inside the hull when its distance to every facet exceeds this
/// fraction of the largest wrench norm (absorbs qhull's round-off; below it epsilon is 0).
constexpr double kClosureTolerance = 1e-10;

/// Facets of the convex hull of a wrench set.
struct WrenchHull {
  /// kOk (hull built), kDegenerate (fewer than 7 points or affine rank < 6),
  /// kInvalidInput (non-finite value), kHullFailed (qhull error, message says which).
  QualityStatus status = QualityStatus::kDegenerate;
  std::string message;  ///< detail when status != kOk
  /// Outward unit facet normals u_f, one per column.
  Eigen::Matrix<double, 6, Eigen::Dynamic> normals;
  /// Facet offsets b_f: u_f . w + b_f = 0 on facet f, < 0 inside. The distance from the origin
  /// to facet f's hyperplane is -b_f when the origin is inside.
  Eigen::VectorXd offsets;
  double volume = 0.0;  ///< 6-D volume of the hull (0 unless kOk)
  /// Largest wrench norm of the input; the scale of kClosureTolerance.
  double scale = 0.0;
  /// True when the facets come from the merging pass "Qx" (the fast pass failed or was off).
  bool merged_pass = false;
};

/// How wrenchHull() runs qhull.
struct WrenchHullOptions {
  /// Check the affine rank with Eigen before qhull (false leaves it to qhull, which then
  /// reports a flat set as a qhull error: for tests of that path).
  bool check_rank = true;
  /// Try the fast non-merging pass "Q0" first (false: only "Qx").
  bool fast_pass = true;
};

/// Screens a wrench set before any hull is built. Returns kInvalidInput (a non-finite value, or
/// too many wrenches), kDegenerate (fewer than 7 wrenches, or with `check_rank` an affine rank
/// below 6 by kDegenerateSpread; the message gives rank and relative thickness) or kOk. Sets
/// `scale` to the largest wrench norm (0 for an empty or non-finite set).
QualityStatus screenWrenches(const WrenchMatrix& wrenches, bool check_rank, double& scale,
                             std::string& message);

/// Builds the convex hull of the columns of `wrenches` with reentrant qhull, its own qhT per
/// call. First pass "Q0 FA" (no facet merging, total volume: about 2.5x faster on cone-edge
/// sets, whose edges are exactly coplanar per contact); it is accepted only if qhull reports
/// no error and every facet is a supporting hyperplane (max_i u_f . w_i = -b_f within
/// kClosureTolerance * scale). Otherwise "Qx FA" (exact pre-merge of coplanar facets). Never
/// "QJ": joggling would perturb epsilon. The affine rank is checked with Eigen first (see
/// WrenchHullOptions). qhull never prints: its error and warning text goes to /dev/null.
WrenchHull wrenchHull(const WrenchMatrix& wrenches, const WrenchHullOptions& options = {});

/// Summary of a hull: force closure iff status is kOk and every facet has
/// -b_f > kClosureTolerance * scale; epsilon = min_f(-b_f) then, 0 otherwise.
/// Fills force_closure, epsilon, volume, status and message of `result`.
void summarizeHull(const WrenchHull& hull, QualityResult& result);

}  // namespace taskmap
