// Convex hull of a 6-D wrench set through reentrant qhull (runQhull of the meshes stage, which
// owns the qhull set-up). Every call owns its qhull instance: threads run in parallel.
#include "taskmap/quality/wrench_hull.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "taskmap/core/text.hpp"
#include "taskmap/meshes/qhull_run.hpp"

namespace taskmap {
namespace {

constexpr int kDim = 6;

/// Runs qhull with `options` on the columns of `wrenches`; on success (returns 0) fills the
/// facets and volume of `hull`. Returns qhull's output (exit code, error).
QhullOutput buildHull(const WrenchMatrix& wrenches, const char* options, WrenchHull& hull) {
  const Eigen::Index n = wrenches.cols();
  // Column-major 6 x n is qhull's point-major layout.
  const std::vector<double> points(wrenches.data(), wrenches.data() + kDim * n);
  QhullOutput q = runQhull(kDim, points, options, true, false);
  if (q.exit_code != 0) return q;
  hull.normals = q.normals;
  hull.offsets = q.offsets;
  hull.volume = q.volume;
  return q;
}

/// Every facet must be a supporting hyperplane: no wrench farther than kClosureTolerance *
/// scale beyond it, and at least one on it (within the same tolerance).
bool facetsSupport(const WrenchMatrix& wrenches, const WrenchHull& hull) {
  if (hull.offsets.size() == 0) return false;
  const double tol = kClosureTolerance * hull.scale;
  if (!hull.normals.allFinite() || !hull.offsets.allFinite()) return false;
  for (Eigen::Index f = 0; f < hull.offsets.size(); ++f) {
    const double highest =
        (hull.normals.col(f).transpose() * wrenches).maxCoeff() + hull.offsets(f);
    if (std::abs(highest) > tol) return false;
  }
  return true;
}

}  // namespace

QualityStatus screenWrenches(const WrenchMatrix& wrenches, bool check_rank, double& scale,
                             std::string& message) {
  const Eigen::Index n = wrenches.cols();
  scale = 0.0;
  if (!wrenches.allFinite()) {
    message = "a wrench is NaN or infinite";
    return QualityStatus::kInvalidInput;
  }
  if (n > 0) scale = wrenches.colwise().norm().maxCoeff();
  if (n < kDim + 1) {
    message = std::to_string(n) + " wrenches cannot span 6 dimensions (7 needed)";
    return QualityStatus::kDegenerate;
  }
  if (n > std::numeric_limits<int>::max() / kDim) {
    message = "too many wrenches for qhull";
    return QualityStatus::kInvalidInput;
  }
  if (!check_rank) return QualityStatus::kOk;
  // Affine rank with Eigen: singular values of the centred wrench matrix from its 6 x 6 Gram
  // matrix (kDegenerateSpread = 1e-7 keeps the eigenvalue ratio at 1e-14, well above the Gram
  // matrix's round-off).
  const Eigen::Matrix<double, 6, 1> mean = wrenches.rowwise().mean();
  WrenchMatrix centred = wrenches.colwise() - mean;
  const double magnitude = centred.cwiseAbs().maxCoeff();
  if (magnitude > 0.0) centred /= magnitude;  // no overflow or underflow in the Gram matrix
  const Eigen::Matrix<double, 6, 6> gram = centred * centred.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(gram,
                                                                       Eigen::EigenvaluesOnly);
  const double lmax = eig.eigenvalues()(kDim - 1);
  const double lmin = eig.eigenvalues()(0);
  if (lmax > 0.0 && lmin > kDegenerateSpread * kDegenerateSpread * lmax) return QualityStatus::kOk;
  int rank = 0;
  for (int i = 0; i < kDim; ++i) {
    rank += eig.eigenvalues()(i) > kDegenerateSpread * kDegenerateSpread * lmax;
  }
  if (!(lmax > 0.0)) rank = 0;
  const std::string thickness =
      shortNumber(lmax > 0.0 ? std::sqrt(std::max(lmin, 0.0) / lmax) : 0.0);
  message = "wrenches span an affine subspace of dimension " + std::to_string(rank) +
            " < 6 (relative thickness " + thickness + ")";
  return QualityStatus::kDegenerate;
}

WrenchHull wrenchHull(const WrenchMatrix& wrenches, const WrenchHullOptions& options) {
  WrenchHull hull;
  hull.status = screenWrenches(wrenches, options.check_rank, hull.scale, hull.message);
  if (hull.status != QualityStatus::kOk) return hull;

  // Fast pass without merging (Q0), verified; exact pre-merging (Qx) when it fails.
  QhullOutput q;
  q.exit_code = -1;
  if (options.fast_pass) q = buildHull(wrenches, "Q0 FA", hull);
  if (q.exit_code != 0 || !facetsSupport(wrenches, hull)) {
    q = buildHull(wrenches, "Qx FA", hull);
    hull.merged_pass = true;
  }
  if (q.exit_code != 0) {
    hull.normals.resize(kDim, 0);
    hull.offsets.resize(0);
    hull.volume = 0.0;
    hull.status = q.singular ? QualityStatus::kDegenerate : QualityStatus::kHullFailed;
    hull.message = "qhull: " + q.error;
    return hull;
  }
  hull.status = QualityStatus::kOk;
  return hull;
}

void summarizeHull(const WrenchHull& hull, QualityResult& result) {
  result.status = hull.status;
  result.message = hull.message;
  result.force_closure = false;
  result.epsilon = 0.0;
  result.volume = hull.status == QualityStatus::kOk ? hull.volume : 0.0;
  if (hull.status != QualityStatus::kOk || hull.offsets.size() == 0) return;
  const double nearest = -hull.offsets.maxCoeff();  // min over facets of -b_f
  if (nearest > kClosureTolerance * hull.scale) {
    result.force_closure = true;
    result.epsilon = nearest;
  }
}

}  // namespace taskmap
