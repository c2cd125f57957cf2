#include "taskmap/integration/criteria.hpp"

#include <cmath>

#include "kernels.hpp"

namespace taskmap {

Twist poseDifference(const Pose& x, const Pose& mu) {
  Twist e;
  e.head<3>() = x.position - mu.position;
  e.tail<3>() =
      detail::relativeLog(mu.orientation.normalized().conjugate(), x.orientation.normalized());
  return e;
}

double proximityCost(const Pose& x, const Pose& mu, double linear_weight, double angular_weight,
                     Twist* gradient) {
  const Twist e = poseDifference(x, mu);
  if (gradient) {
    const Eigen::Matrix3d r = x.orientation.normalized().toRotationMatrix();
    gradient->head<3>() = 2.0 * linear_weight * e.head<3>();
    // R J_r^{-1}(w)^T (2 w_r w) = 2 w_r R w (criteria.hpp).
    gradient->tail<3>() = 2.0 * angular_weight * (r * e.tail<3>());
  }
  return linear_weight * e.head<3>().squaredNorm() + angular_weight * e.tail<3>().squaredNorm();
}

double gaussianNormaliser(double position_sigma, double rotation_sigma) {
  const double two_pi = 2.0 * M_PI;
  return two_pi * two_pi * two_pi * std::pow(position_sigma * rotation_sigma, 3);
}

double gaussianDensity(const Pose& x, const Pose& mu, double position_sigma, double rotation_sigma,
                       Twist* gradient) {
  const Eigen::Vector3d dp = x.position - mu.position;
  const Eigen::Matrix3d r = x.orientation.normalized().toRotationMatrix();
  const Eigen::Matrix3d dr = mu.orientation.normalized().toRotationMatrix() - r;  // R_mu - R
  const double isp2 = 1.0 / (position_sigma * position_sigma);
  const double isr2 = 1.0 / (rotation_sigma * rotation_sigma);
  const double d = dp.squaredNorm() * isp2 + 0.5 * dr.squaredNorm() * isr2;
  const double f = std::exp(-0.5 * d) / gaussianNormaliser(position_sigma, rotation_sigma);
  if (gradient) {
    // df = -f/2 dd; dd/dp = 2 dp / sp^2, dd/dw = v(R R_mu^T) / sr^2 = v(R (R_mu - R)^T) / sr^2
    // (v(I) = 0; criteria.hpp).
    gradient->head<3>() = -f * isp2 * dp;
    gradient->tail<3>() = (-0.5 * f * isr2) * detail::skewOfProduct(r, dr);
  }
  return f;
}

}  // namespace taskmap
