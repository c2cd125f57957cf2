#pragma once
/// @file hull_oracles.hpp
/// Independent references for the quality tests, sharing no code with qhull or
/// taskmap::wrenchHull:
///  - a dense two-phase simplex (Bland's rule) for force closure and ray-shooting distances;
///  - a brute-force facet enumeration over all 6-point subsets for exact epsilon on small sets.

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Dense>

namespace taskmap::testing {

using Wrenches = Eigen::Matrix<double, 6, Eigen::Dynamic>;

/// Result of max c.x s.t. A x = b, x >= 0.
struct LpResult {
  bool feasible = false;
  bool bounded = true;
  double value = 0.0;
  Eigen::VectorXd x;
};

/// Two-phase revised simplex with Bland's rule (no cycling on degenerate LPs). Every
/// iteration refactorises the basis from the original data (m is 7 here), so round-off does
/// not accumulate over pivots.
inline LpResult solveLp(Eigen::MatrixXd a, Eigen::VectorXd b, const Eigen::VectorXd& c) {
  const int m = static_cast<int>(a.rows()), n = static_cast<int>(a.cols());
  for (int i = 0; i < m; ++i) {
    if (b(i) < 0) {
      a.row(i) *= -1.0;
      b(i) *= -1.0;
    }
  }
  // Columns: n structural, then m artificial (identity).
  Eigen::MatrixXd full(m, n + m);
  full.leftCols(n) = a;
  full.rightCols(m).setIdentity();
  std::vector<int> basis(m);
  for (int i = 0; i < m; ++i) basis[i] = n + i;
  const double tol = 1e-12 * std::max(1.0, a.cwiseAbs().maxCoeff());

  auto basisMatrix = [&] {
    Eigen::MatrixXd bm(m, m);
    for (int i = 0; i < m; ++i) bm.col(i) = full.col(basis[i]);
    return bm;
  };
  // Maximises obj over columns < limit (artificials >= limit may stay basic at zero).
  auto run = [&](const Eigen::VectorXd& obj, int limit) -> bool {
    for (int iter = 0; iter < 100000; ++iter) {
      const Eigen::PartialPivLU<Eigen::MatrixXd> lu(basisMatrix());
      const Eigen::VectorXd xb = lu.solve(b);
      Eigen::VectorXd cb(m);
      for (int i = 0; i < m; ++i) cb(i) = obj(basis[i]);
      const Eigen::VectorXd y = lu.transpose().solve(cb);
      int enter = -1;
      for (int j = 0; j < limit; ++j) {
        if (std::find(basis.begin(), basis.end(), j) != basis.end()) continue;
        if (obj(j) - y.dot(full.col(j)) > tol) {
          enter = j;  // Bland: smallest index
          break;
        }
      }
      if (enter < 0) return true;
      const Eigen::VectorXd d = lu.solve(full.col(enter));
      int leave = -1;
      double best = std::numeric_limits<double>::infinity();
      for (int i = 0; i < m; ++i) {
        // A basic artificial (at zero after phase 1) blocks any move that would change it.
        const bool artificial = basis[i] >= limit;
        if (d(i) > 1e-12 || (artificial && std::abs(d(i)) > 1e-12)) {
          const double ratio = artificial ? 0.0 : std::max(xb(i), 0.0) / d(i);
          if (leave < 0 || ratio < best - 1e-14 ||
              (ratio <= best + 1e-14 && basis[i] < basis[leave])) {
            best = std::min(best, ratio);
            leave = i;
          }
        }
      }
      if (leave < 0) return false;  // unbounded
      basis[leave] = enter;
    }
    return true;
  };

  LpResult res;
  Eigen::VectorXd phase1 = Eigen::VectorXd::Zero(n + m);
  phase1.tail(m).setConstant(-1.0);
  run(phase1, n + m);
  Eigen::VectorXd xb = basisMatrix().partialPivLu().solve(b);
  double infeas = 0.0;
  for (int i = 0; i < m; ++i) {
    if (basis[i] >= n) infeas += std::abs(xb(i));
  }
  if (infeas > 1e-9) return res;
  res.feasible = true;
  // Phase 2: artificials never re-enter; any still basic sit at zero and leave at the first
  // pivot that would move them.
  Eigen::VectorXd phase2 = Eigen::VectorXd::Zero(n + m);
  phase2.head(n) = c;
  if (!run(phase2, n)) {
    res.bounded = false;
    return res;
  }
  xb = basisMatrix().partialPivLu().solve(b);
  res.x = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < m; ++i) {
    if (basis[i] < n) res.x(basis[i]) = xb(i);
  }
  res.value = c.dot(res.x);
  return res;
}

/// Affine rank of the columns, from a full SVD of the centred matrix (threshold relative 1e-7,
/// the documented kDegenerateSpread).
inline int affineRank(const Wrenches& w) {
  if (w.cols() < 2) return 0;
  const Wrenches centred = w.colwise() - w.rowwise().mean();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(centred);
  const auto s = svd.singularValues();
  int r = 0;
  for (int i = 0; i < s.size(); ++i) r += s(i) > 1e-7 * s(0);
  return r;
}

/// LP margin: max t s.t. sum_i lambda_i w_i = 0, sum lambda_i = 1, lambda_i >= t >= 0.
/// Returns -1 when the origin is outside conv(w). The origin is in the relative interior iff
/// the margin is > 0; with affine rank 6 that is the interior (force closure).
inline double closureMargin(const Wrenches& w) {
  const int n = static_cast<int>(w.cols());
  // Variables: mu_i = lambda_i - t >= 0 (n of them), then t >= 0.
  Eigen::MatrixXd a(7, n + 1);
  a.topLeftCorner(6, n) = w;
  a.topRightCorner(6, 1) = w.rowwise().sum();
  a.bottomLeftCorner(1, n).setOnes();
  a(6, n) = n;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(7);
  b(6) = 1.0;
  Eigen::VectorXd c = Eigen::VectorXd::Zero(n + 1);
  c(n) = 1.0;
  const LpResult r = solveLp(a, b, c);
  if (!r.feasible) return -1.0;
  return r.value;
}

/// Ray shooting: max s >= 0 with s u in conv(w) (the origin inside). Distance from the origin
/// to the hull boundary along the unit direction u.
inline double rayDistance(const Wrenches& w, const Eigen::Matrix<double, 6, 1>& u) {
  const int n = static_cast<int>(w.cols());
  // Variables: lambda (n), s. sum lambda_i w_i - s u = 0, sum lambda = 1.
  Eigen::MatrixXd a(7, n + 1);
  a.topLeftCorner(6, n) = w;
  a.topRightCorner(6, 1) = -u;
  a.bottomLeftCorner(1, n).setOnes();
  a(6, n) = 0.0;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(7);
  b(6) = 1.0;
  Eigen::VectorXd c = Eigen::VectorXd::Zero(n + 1);
  c(n) = 1.0;
  const LpResult r = solveLp(a, b, c);
  if (!r.feasible) return -1.0;
  return r.value;
}

/// Brute force over all 6-subsets: every affinely independent 6-subset spans a hyperplane; it
/// supports conv(w) when all points lie on one side. The origin is strictly inside iff every
/// supporting hyperplane has the origin strictly on the inner side; epsilon is then the least
/// distance from the origin to a supporting hyperplane. Returns epsilon, or 0 when not inside.
/// Only for small sets (C(N, 6) subsets) with affine rank 6.
inline double bruteForceEpsilon(const Wrenches& w, bool* inside = nullptr) {
  const int n = static_cast<int>(w.cols());
  const double scale = w.colwise().norm().maxCoeff();
  const double side_tol = 1e-10 * scale;
  double eps = std::numeric_limits<double>::infinity();
  bool origin_inside = true;
  int idx[6];
  for (int i = 0; i < 6; ++i) idx[i] = i;
  while (true) {
    Eigen::Matrix<double, 6, 5> d;
    for (int k = 1; k < 6; ++k) d.col(k - 1) = w.col(idx[k]) - w.col(idx[0]);
    // Normal: orthogonal complement of the 5 edge vectors (full QR, last column of Q).
    Eigen::HouseholderQR<Eigen::Matrix<double, 6, 5>> qr(d);
    const Eigen::Matrix<double, 6, 6> q =
        qr.householderQ() * Eigen::Matrix<double, 6, 6>::Identity();
    const auto rdiag = qr.matrixQR().diagonal();
    double rmin = std::numeric_limits<double>::infinity(), rmax = 0.0;
    for (int k = 0; k < 5; ++k) {
      rmin = std::min(rmin, std::abs(rdiag(k)));
      rmax = std::max(rmax, std::abs(rdiag(k)));
    }
    if (rmin > 1e-9 * std::max(rmax, 1e-300)) {
      Eigen::Matrix<double, 6, 1> u = q.col(5);
      double off = u.dot(w.col(idx[0]));
      const Eigen::VectorXd proj = u.transpose() * w;
      double hi = proj.maxCoeff() - off, lo = proj.minCoeff() - off;
      bool supporting = false;
      if (hi <= side_tol) {
        supporting = true;  // all points below: u outward, offset off
      } else if (lo >= -side_tol) {
        supporting = true;
        u = -u;
        off = -off;
      }
      if (supporting) {
        // Origin's signed distance below the hyperplane u.x = off is off.
        if (off <= side_tol) origin_inside = false;
        eps = std::min(eps, off);
      }
    }
    // Next combination.
    int k = 5;
    while (k >= 0 && idx[k] == n - 6 + k) --k;
    if (k < 0) break;
    ++idx[k];
    for (int j = k + 1; j < 6; ++j) idx[j] = idx[j - 1] + 1;
  }
  if (inside) *inside = origin_inside;
  return origin_inside ? eps : 0.0;
}

}  // namespace taskmap::testing
