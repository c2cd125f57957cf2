#pragma once
// Private inline kernels shared by criteria.cpp and task_map.cpp.

#include <cmath>
#include <cstddef>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/core/pose.hpp"

namespace taskmap {
namespace detail {

/// log of the rotation conj(qm) * q (= R_m^T R) as a rotation vector, angle in [0, pi].
/// qm_conj is the conjugate of the sample's unit quaternion, q the query's unit quaternion.
inline Eigen::Vector3d relativeLog(const Eigen::Quaterniond& qm_conj, const Eigen::Quaterniond& q) {
  Eigen::Quaterniond r = qm_conj * q;
  double w = r.w();
  Eigen::Vector3d v = r.vec();
  if (w < 0) {
    w = -w;
    v = -v;
  }
  const double s = v.norm();
  if (s < 1e-9) return (2.0 / w) * v;  // theta = 2 atan(s / w) = 2 s / w + O(s^3)
  return (2.0 * std::atan2(s, w) / s) * v;
}

/// Above this Mahalanobis distance exp(-d / 2) is exactly 0 in double precision
/// (exp(x) rounds to 0 for x < -745.14), so the exp call can be skipped.
constexpr double kKernelUnderflow = 1492.0;

/// Running sums of a quality mixture over embedded samples: with c_i = w_i exp(-d_i / 2),
/// sum = sum c_i and moment = sum c_i (x_i - x) (12-D embedding differences).
struct MixtureSum {
  double sum = 0.0;
  double moment[kEmbeddingDim] = {};
  double included_weight = 0.0;  ///< sum of w_i over the terms added
  std::size_t terms = 0;         ///< terms with w_i > 0
};

/// The quality kernel's Mahalanobis distance in the embedding (p, (rho/sqrt2) vec R):
/// d = |x_i,p - x_p|^2 inv_sp2 + |x_i,R - x_R|^2 inv_se2 with inv_sp2 = 1/sp^2 and
/// inv_se2 = 1/(rho sr)^2, so that the rotation part is ||R_i - R||_F^2 / (2 sr^2)
/// (criteria.hpp), from the differences diff = x_i - x (12 doubles).
inline double mixtureDistance(const double* diff, double inv_sp2, double inv_se2) {
  double dp2 = 0.0, dr2 = 0.0;
  for (int k = 0; k < 3; ++k) dp2 += diff[k] * diff[k];
  for (int k = 3; k < kEmbeddingDim; ++k) dr2 += diff[k] * diff[k];
  return dp2 * inv_sp2 + dr2 * inv_se2;
}

/// Adds the term c = w exp(-d / 2) with the differences diff (12 doubles) to m, given
/// e = exp(-d / 2) (0 if d >= kKernelUnderflow): the part of addMixtureDifference after the exp.
inline void addMixtureExp(const double* diff, double w, double e, MixtureSum& m) {
  const double c = w * e;
  m.sum += c;
  for (int k = 0; k < kEmbeddingDim; ++k) m.moment[k] += c * diff[k];
  m.included_weight += w;
  ++m.terms;
}

/// addMixtureExp for the terms t < n with differences diffs + 12 t, weights[t] and exps[t], in
/// order: the same arithmetic, the moment's twelve sums two at a time.
inline void addMixtureExps(const double* diffs, const double* weights, const double* exps,
                           std::size_t n, MixtureSum& m) {
#if defined(__SSE2__)
  static_assert(kEmbeddingDim == 12, "six pairs");
  __m128d moment[6];
  for (int j = 0; j < 6; ++j) moment[j] = _mm_loadu_pd(m.moment + 2 * j);
  for (std::size_t t = 0; t < n; ++t) {
    const double c = weights[t] * exps[t];
    m.sum += c;
    const __m128d cc = _mm_set1_pd(c);
    const double* diff = diffs + t * kEmbeddingDim;
    for (int j = 0; j < 6; ++j)
      moment[j] = _mm_add_pd(moment[j], _mm_mul_pd(cc, _mm_loadu_pd(diff + 2 * j)));
    m.included_weight += weights[t];
  }
  for (int j = 0; j < 6; ++j) _mm_storeu_pd(m.moment + 2 * j, moment[j]);
  m.terms += n;
#else
  for (std::size_t t = 0; t < n; ++t)
    addMixtureExp(diffs + t * kEmbeddingDim, weights[t], exps[t], m);
#endif
}

/// Adds the sample with embedding differences diff = x_i - x (12 doubles) and weight w > 0 to
/// m: c = w exp(-d / 2) with d = mixtureDistance (addMixtureTerm computes diff and w).
inline void addMixtureDifference(const double* diff, double w, double inv_sp2, double inv_se2,
                                 MixtureSum& m) {
  const double d = mixtureDistance(diff, inv_sp2, inv_se2);
  addMixtureExp(diff, w, d < kKernelUnderflow ? std::exp(-0.5 * d) : 0.0, m);  // else c = 0
}

/// Adds the sample x_i = row[0..11] with weight w_i = row[12] (if > 0) to m, at the query
/// embedding x (12 doubles): addMixtureDifference, the same arithmetic term by term.
inline void addMixtureTerm(const double* row, const double* x, double inv_sp2, double inv_se2,
                           MixtureSum& m) {
  const double w = row[kEmbeddingDim];
  if (w <= 0) return;
  double diff[kEmbeddingDim];  // x_i - x
  for (int k = 0; k < kEmbeddingDim; ++k) diff[k] = row[k] - x[k];
  addMixtureDifference(diff, w, inv_sp2, inv_se2, m);
}

/// v(R M^T) with v(A) = (A21 - A12, A02 - A20, A10 - A01), i.e. twice the axial vector of the
/// skew part of R M^T. For a rotation M: d tr(M^T exp(w^) R) / dw at w = 0 is -v(R M^T).
inline Eigen::Vector3d skewOfProduct(const Eigen::Matrix3d& r, const Eigen::Matrix3d& m) {
  const Eigen::Matrix3d a = r * m.transpose();
  return Eigen::Vector3d(a(2, 1) - a(1, 2), a(0, 2) - a(2, 0), a(1, 0) - a(0, 1));
}

/// The rotation block of an embedding difference (9 doubles, rho/sqrt2 vec(dR), column-major)
/// back in rotation-matrix units: dR.
inline Eigen::Matrix3d rotationBlock(const double* nine, double rho) {
  return Eigen::Map<const Eigen::Matrix3d>(nine) * (std::sqrt(2.0) / rho);
}

}  // namespace detail
}  // namespace taskmap
