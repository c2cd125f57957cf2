// Zheng's support-function refinement for force closure and epsilon (see wrench_epsilon.hpp),
// on the incremental hull of incremental_hull.hpp; qhull answers when that hull gives up.
#include "taskmap/quality/wrench_epsilon.hpp"

#include <string>

#include "incremental_hull.hpp"
#include "taskmap/quality/squeeze_balance.hpp"

namespace taskmap {
namespace {

/// Runs the refinement on `hull`; false when the incremental hull failed.
bool refine(const WrenchMatrix& w, detail::IncrementalHull& hull, WrenchEpsilon& out) {
  const double closure = kClosureTolerance * out.scale;
  const double tol = kIncrementalHullTolerance * out.scale;
  const Eigen::Index n = w.cols();
  // Every pass inserts a wrench that is not yet a vertex, so at most n - 7 passes.
  for (Eigen::Index pass = 0; pass <= n; ++pass) {
    const int f = hull.nearestFacet();
    const auto& facet = hull.facet(f);
    Eigen::Index top = 0;
    const double support = (facet.normal.transpose() * w).maxCoeff(&top);
    if (support <= facet.offset + tol || support <= closure) {
      // Either the facet supports the whole set (it is a facet of the true hull, and the
      // nearest one), or the set lies in a half-space whose boundary passes within the closure
      // tolerance of the origin.
      out.force_closure = support > closure && facet.offset > closure;
      out.epsilon = out.force_closure ? facet.offset : 0.0;
      return true;
    }
    if (!hull.addPoint(static_cast<int>(top), f)) return false;
  }
  return false;
}

/// Whether `mode` asks for the volume of a set with this force-closure outcome.
bool wantsVolume(VolumeMode mode, bool force_closure) {
  return mode == VolumeMode::kAlways || (mode == VolumeMode::kForceClosure && force_closure);
}

}  // namespace

bool hullMissesOrigin(const WrenchMatrix& wrenches, double scale) {
  Eigen::MatrixXd a(7, wrenches.cols());
  a.topRows(6) = wrenches / scale;
  a.row(6).setOnes();
  Eigen::VectorXd b = Eigen::VectorXd::Zero(7);
  b(6) = 1.0;
  double residual = 0.0;
  nonNegativeLeastSquares(a, b, &residual);
  return residual > kClosurePretestMiss;
}

WrenchEpsilon wrenchEpsilon(const WrenchMatrix& wrenches, const WrenchEpsilonOptions& options) {
  WrenchEpsilon out;
  out.status = screenWrenches(wrenches, options.check_rank, out.scale, out.message);
  if (out.status != QualityStatus::kOk) return out;
  if (options.closure_pretest && !wantsVolume(options.volume, false) &&
      hullMissesOrigin(wrenches, out.scale)) {
    out.pretest_rejected = true;  // not force closure, epsilon and volume 0
    return out;
  }

  // One hull per thread, reused: its buffers keep their capacity between grasps.
  thread_local detail::IncrementalHull hull;
  hull.reset(wrenches, kIncrementalHullTolerance * out.scale);
  bool ok = hull.initSimplex() && refine(wrenches, hull, out);
  if (ok && wantsVolume(options.volume, out.force_closure)) {
    ok = hull.complete();
    if (ok) out.volume = hull.volume();
  }
  out.inserted = hull.insertedPoints();
  out.facets = static_cast<int>(hull.aliveFacets().size());
  out.created_facets = hull.createdFacets();
  if (ok) return out;

  out.force_closure = false;
  out.epsilon = 0.0;
  out.volume = 0.0;
  if (!options.allow_qhull) {
    out.status = QualityStatus::kHullFailed;
    out.message =
        std::string("incremental hull failed: ") + hull.failure() + " (qhull fallback disabled)";
    return out;
  }
  WrenchHullOptions qhull_options;
  qhull_options.check_rank = options.check_rank;
  const WrenchHull qhull = wrenchHull(wrenches, qhull_options);
  QualityResult summary;
  summarizeHull(qhull, summary);
  out.status = summary.status;
  out.message = summary.message;
  out.force_closure = summary.force_closure;
  out.epsilon = summary.epsilon;
  out.volume = wantsVolume(options.volume, out.force_closure) ? summary.volume : 0.0;
  out.used_qhull = true;
  return out;
}

}  // namespace taskmap
