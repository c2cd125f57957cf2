#pragma once
/// @file criteria.hpp
/// The two task-map criteria of the paper (eq. 1.18-1.21) for ONE map sample, as plain
/// functions: TaskMap sums them over samples; tests use them as brute-force oracles.
///
/// Proximity uses the pose difference below; the quality kernel (gaussianDensity) is a
/// Gaussian in the 12-D pose embedding instead (no log map), see there.
///
/// Pose difference (docs/METHOD.md §4): e(x, mu) = (p - p_mu, log(R_mu^T R)), a 6-vector
/// (metres, radians). Gradients are 6-vectors (linear, angular) in the OBJECT frame with
/// respect to the perturbation  p <- p + dp,  R <- exp(dw) R  (dw a rotation vector expressed
/// in the object frame, applied on the left of the hand orientation).
///
/// Derivation of the angular part: R_mu^T exp(dw) R = (R_mu^T R) exp(R^T dw), so
/// d log(R_mu^T R) = J_r^{-1}(w) R^T dw with w = log(R_mu^T R). The gradient of any function
/// h(w) is therefore R J_r^{-1}(w)^T dh/dw; for h = c |w|^2 this is 2c R w because
/// J_r^{-1}(w)^T w = w exactly (the skew terms annihilate w).

#include "taskmap/core/pose.hpp"

namespace taskmap {

/// Pose difference (p - p_mu, log(R_mu^T R)) in (metres, radians). The rotation part is
/// expressed in the frame of mu's orientation; its norm is the geodesic angle in [0, pi].
Twist poseDifference(const Pose& x, const Pose& mu);

/// Proximity cost (eq. 1.18) g_p = e^T W e, W = diag(w_p I3, w_r I3); if gradient is not null
/// it receives dg_p/dx (eq. 1.19) in the object frame (see the file comment).
/// @param linear_weight w_p in 1/m^2. @param angular_weight w_r in 1/rad^2.
double proximityCost(const Pose& x, const Pose& mu, double linear_weight, double angular_weight,
                     Twist* gradient = nullptr);

/// Quality kernel (eq. 1.20) of one sample: a normalised Gaussian in the pose embedding
/// (p, (rho/sqrt2) vec R) of docs/METHOD.md §4, f = exp(-d/2) / Z with
///   d = |p - p_mu|^2 / sp^2 + ||R - R_mu||_F^2 / (2 sr^2),   Z = (2 pi)^3 sp^3 sr^3.
/// The rotation factor is the isotropic matrix-Fisher distribution on SO(3):
/// ||R - R_mu||_F^2 = 2 (2 sin(theta/2))^2, so d = |dp|^2/sp^2 + (2 sin(theta/2))^2/sr^2, which
/// is the paper's Gaussian in the tangent space (k = 6, Sigma = diag(sp^2 I3, sr^2 I3), d with
/// theta^2) to second order in theta, with its normaliser (exact as sr -> 0). It does not
/// depend on rho; with sr = sp / rho, d is (pose distance / sp)^2, the index's own distance.
/// If gradient is not null it receives df/dx in the object frame: df = -f/2 dd with
/// dd/dp = 2 dp / sp^2 and dd/dw = v(R R_mu^T) / sr^2, v(A) = (A21 - A12, A02 - A20, A10 - A01)
/// (from R <- exp(w^) R: d tr(R_mu^T exp(w^) R) = tr(w^ R R_mu^T) = -w . v(R R_mu^T), and
/// ||R - R_mu||_F^2 = 6 - 2 tr(R_mu^T R)). @param position_sigma sp, metres (> 0).
/// @param rotation_sigma sr, radians (> 0).
double gaussianDensity(const Pose& x, const Pose& mu, double position_sigma, double rotation_sigma,
                       Twist* gradient = nullptr);

/// The normaliser Z = (2 pi)^3 sp^3 sr^3 of gaussianDensity; 1/Z is the density's peak value.
double gaussianNormaliser(double position_sigma, double rotation_sigma);

}  // namespace taskmap
