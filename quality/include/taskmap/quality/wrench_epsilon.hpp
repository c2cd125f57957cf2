#pragma once
/// @file wrench_epsilon.hpp
/// Force closure and Ferrari-Canny epsilon of a 6-D wrench set without building its whole
/// convex hull: Zheng's support-function refinement of an inner hull (Y. Zheng, "An efficient
/// algorithm for a grasp quality measure", IEEE T-RO 29(2), 2013). evaluateGrasp() uses it;
/// qhull (wrenchHull) answers whenever the incremental hull reports a precision problem.
/// Thread-safe: no global state, no lock.

#include <string>

#include "taskmap/quality/wrench_hull.hpp"

namespace taskmap {

/// Distance (relative to the largest wrench norm) within which a wrench counts as on a facet
/// hyperplane of the incremental hull; also the accuracy of epsilon (absolute, times scale).
constexpr double kIncrementalHullTolerance = 1e-12;

/// What wrenchEpsilon computes besides force closure and epsilon.
struct WrenchEpsilonOptions {
  /// Which sets also get the hull volume (that inserts every remaining wrench).
  VolumeMode volume = VolumeMode::kNever;
  bool check_rank = true;   ///< affine-rank screen first (see WrenchHullOptions::check_rank)
  bool allow_qhull = true;  ///< fall back to qhull on trouble (false: report kHullFailed)
  /// Before the hull, the origin's distance to the hull by non-negative least squares; a set
  /// whose hull misses the origin by more than kClosurePretestMiss x scale is not force closure
  /// (no hull built unless the volume is wanted for every set).
  bool closure_pretest = false;
};

/// Distance from the origin to the wrenches' hull (relative to the largest wrench norm) above
/// which the pre-test declares a set not force closure.
constexpr double kClosurePretestMiss = 1e-9;

/// Outcome of wrenchEpsilon.
struct WrenchEpsilon {
  /// kOk, kDegenerate (fewer than 7 wrenches or affine rank < 6), kInvalidInput (non-finite),
  /// kHullFailed (both the incremental hull and qhull failed; message says why).
  QualityStatus status = QualityStatus::kDegenerate;
  std::string message;            ///< detail when status != kOk
  bool force_closure = false;     ///< epsilon > kClosureTolerance * scale
  double epsilon = 0.0;           ///< distance from the origin to the nearest facet; 0 if not FC
  double volume = 0.0;            ///< 6-D hull volume when options.volume asks for it, else 0
  double scale = 0.0;             ///< largest wrench norm
  int inserted = 0;               ///< wrenches inserted into the inner hull (7..n)
  int facets = 0;                 ///< facets of the inner hull at the end
  int created_facets = 0;         ///< facets created in total (the work done)
  bool used_qhull = false;        ///< the answer came from qhull (incremental hull failed)
  bool pretest_rejected = false;  ///< the closure pre-test found the origin outside the hull
};

/// Whether the origin lies farther than kClosurePretestMiss x scale outside the convex hull of
/// the columns of `wrenches` (scale: the largest column norm, > 0). Non-negative least squares
/// (Lawson-Hanson) on min |W l / scale|^2 + (sum l - 1)^2 over l >= 0: 0 when the origin is in
/// the hull; at most d^2 (the hull's nearest point) and at least d^2 / (1 + d^2) when it is at
/// relative distance d outside. So a residual above the threshold proves d above it: not force
/// closure (docs/METHOD.md §4c).
bool hullMissesOrigin(const WrenchMatrix& wrenches, double scale);

/// Force closure and epsilon of the convex hull of the columns of `wrenches`.
/// Method: start from a 6-simplex of the wrenches; repeat: take the inner hull's facet nearest
/// to the origin (signed offset b, unit normal u); compute the support h = max_i u . w_i; if
/// h <= b + tol the facet supports the whole set, so epsilon = b when b > kClosureTolerance *
/// scale and the grasp is not force closure otherwise; if h <= kClosureTolerance * scale the
/// set lies in a half-space through the origin (not force closure); else insert the support
/// wrench (beneath-beyond) and repeat. Because the inner hull lies inside the true hull, its
/// nearest facet is never farther than the true one; when that facet supports the whole set it
/// is a true facet, so the answer is exact (error <= kIncrementalHullTolerance * scale).
WrenchEpsilon wrenchEpsilon(const WrenchMatrix& wrenches, const WrenchEpsilonOptions& options = {});

}  // namespace taskmap
