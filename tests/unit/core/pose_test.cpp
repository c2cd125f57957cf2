#include "taskmap/core/pose.hpp"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "taskmap/core/constants.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/random.hpp"

namespace taskmap {
namespace {

TEST(PoseTest, QuaternionSignDoesNotChangeDistance) {
  Rng rng(7);
  for (int i = 0; i < 1000; ++i) {
    Pose a{rng.direction(), rng.rotation()};
    Pose b = a;
    b.orientation.coeffs() *= -1.0;
    EXPECT_NEAR(poseDistance(a, b, 0.1), 0.0, 1e-7);
    EXPECT_NEAR((embedPose(a, 0.1) - embedPose(b, 0.1)).norm(), 0.0, 1e-12);
  }
}

TEST(PoseTest, HalfTurnIsTwoRho) {
  const double rho = 0.13;
  Pose a;
  Pose b;
  b.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(kPi, Eigen::Vector3d(1, 2, 3).normalized()));
  EXPECT_NEAR(poseDistance(a, b, rho), 2.0 * rho, 1e-12);
}

TEST(PoseTest, EmbeddingDistanceEqualsPoseDistance) {
  Rng rng(11);
  for (int i = 0; i < 2000; ++i) {
    const double rho = rng.uniform(0.01, 0.5);
    Pose a{rng.direction() * rng.uniform(), rng.rotation()};
    Pose b{rng.direction() * rng.uniform(), rng.rotation()};
    // Brute-force oracle: geodesic angle from the relative rotation matrix.
    const Eigen::Matrix3d rel =
        a.orientation.toRotationMatrix().transpose() * b.orientation.toRotationMatrix();
    const double theta = std::acos(std::clamp((rel.trace() - 1.0) / 2.0, -1.0, 1.0));
    const double chord = 2.0 * std::sin(theta / 2.0);
    const double expected =
        std::sqrt((a.position - b.position).squaredNorm() + rho * rho * chord * chord);
    EXPECT_NEAR(poseDistance(a, b, rho), expected, 1e-7);
    EXPECT_NEAR((embedPose(a, rho) - embedPose(b, rho)).norm(), expected, 1e-7);
    EXPECT_NEAR(rotationAngle(a.orientation, b.orientation), theta, 1e-6);
  }
}

TEST(PoseTest, UnembedInvertsEmbed) {
  Rng rng(3);
  for (int i = 0; i < 200; ++i) {
    Pose a{rng.direction(), rng.rotation()};
    Pose b = unembedPose(embedPose(a, 0.2), 0.2);
    EXPECT_NEAR(poseDistance(a, b, 0.2), 0.0, 1e-7);
  }
}

TEST(PoseTest, LogExpRoundTripAndJacobian) {
  Rng rng(5);
  for (int i = 0; i < 500; ++i) {
    Eigen::Vector3d w = rng.direction() * rng.uniform(0.0, 3.0);
    EXPECT_NEAR((rotationLog(rotationExp(w)) - w).norm(), 0.0, 1e-9);
    // d log(R exp(dw)) / d dw = J_r^{-1}(w), checked by central differences.
    const Eigen::Matrix3d r = rotationExp(w);
    const Eigen::Matrix3d jinv = rightJacobianInverse(w);
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d e = Eigen::Vector3d::Zero();
      e[k] = h;
      const Eigen::Vector3d fd =
          (rotationLog(r * rotationExp(e)) - rotationLog(r * rotationExp(-e))) / (2 * h);
      EXPECT_NEAR((fd - jinv.col(k)).norm(), 0.0, 1e-6);
    }
  }
}

TEST(PoseTest, Vector7RoundTripAndErrors) {
  Eigen::Matrix<double, 7, 1> v;
  v << 1, 2, 3, -0.5, 0.5, 0.5, 0.5;
  Pose p = Pose::fromVector7(v);
  Eigen::Matrix<double, 7, 1> w = p.toVector7();
  EXPECT_GE(w[3], 0.0);
  EXPECT_NEAR(poseDistance(p, Pose::fromVector7(w), 1.0), 0.0, 1e-12);
  v[3] = std::nan("");
  EXPECT_THROW(Pose::fromVector7(v), Error);
  v << 0, 0, 0, 0, 0, 0, 0;
  EXPECT_TRUE(testing::throwsError([&] { Pose::fromVector7(v); }, {"zero norm"}));
}

TEST(PoseTest, MeanOrientationIsSignInvariant) {
  Rng rng(9);
  const Eigen::Quaterniond base = rng.rotation();
  std::vector<Eigen::Quaterniond> qs;
  for (int i = 0; i < 50; ++i) {
    Eigen::Quaterniond q = base * Eigen::Quaterniond(rotationExp(rng.direction() * 0.05));
    if (i % 2) q.coeffs() *= -1.0;
    qs.push_back(q);
  }
  EXPECT_LT(rotationAngle(meanOrientation(qs), base), 0.03);
  EXPECT_THROW(meanOrientation({}), Error);
}

}  // namespace
}  // namespace taskmap
