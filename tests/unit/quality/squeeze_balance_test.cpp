// Squeeze balance: non-negative least squares against its optimality conditions, and
// two-jaw grasps whose equilibrium is known by hand (equal efforts balance, unequal do not;
// friction resists a sideways push only when the squeeze is strong enough).
#include "taskmap/quality/squeeze_balance.hpp"

#include <gtest/gtest.h>

#include <random>

#include "error_matchers.hpp"

namespace taskmap {
namespace {

TEST(NonNegativeLeastSquares, MeetsTheOptimalityConditions) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const int rows = 3 + trial % 8, cols = 2 + (trial * 7) % 30;
    Eigen::MatrixXd a(rows, cols);
    Eigen::VectorXd b(rows);
    for (int i = 0; i < rows; ++i) {
      b(i) = n(rng);
      for (int j = 0; j < cols; ++j) a(i, j) = n(rng);
    }
    double residual = -1.0;
    const Eigen::VectorXd x = nonNegativeLeastSquares(a, b, &residual);
    EXPECT_NEAR(residual, (a * x - b).norm(), 1e-9);
    const Eigen::VectorXd w = a.transpose() * (b - a * x);  // minus the gradient
    for (int j = 0; j < cols; ++j) {
      EXPECT_GE(x(j), 0.0);
      EXPECT_LE(w(j), 1e-7) << "trial " << trial;  // no descent direction left
      if (x(j) > 1e-9) {                           // complementarity
        EXPECT_NEAR(w(j), 0.0, 1e-7);
      }
    }
  }
}

TEST(NonNegativeLeastSquares, ReachesAnExactNonNegativeSolution) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::MatrixXd a = Eigen::MatrixXd::Random(6, 20);
  Eigen::VectorXd x0(20);
  for (int j = 0; j < 20; ++j) x0(j) = j % 3 == 0 ? u(rng) : 0.0;
  double residual = 1.0;
  nonNegativeLeastSquares(a, a * x0, &residual);
  EXPECT_LT(residual, 1e-9);
}

/// Two jaws pressing a 4 cm block along x: contact i at x = -+0.02, outward normal -+x; jaw i
/// (prismatic, one joint each) pushes along +-x with effort e_i.
struct Jaws {
  std::vector<Contact> contacts;
  SqueezeDrive drive;
  Jaws(double e0, double e1) {
    Contact left, right;
    left.point = Eigen::Vector3d(-0.02, 0, 0);
    left.normal = -Eigen::Vector3d::UnitX();
    right.point = Eigen::Vector3d(0.02, 0, 0);
    right.normal = Eigen::Vector3d::UnitX();
    contacts = {left, right};
    Eigen::Matrix<double, Eigen::Dynamic, 3> j0 =
        Eigen::Matrix<double, Eigen::Dynamic, 3>::Zero(2, 3);
    Eigen::Matrix<double, Eigen::Dynamic, 3> j1 = j0;
    j0(0, 0) = 1.0;   // jaw 0 moves its contact along +x as q0 grows
    j1(1, 0) = -1.0;  // jaw 1 along -x
    drive.jacobians = {j0, j1};
    drive.effort = Eigen::Vector2d(e0, e1);
    drive.lever = Eigen::Vector2d(1.0, 1.0);
  }
};

TEST(SqueezeBalance, EqualJawsBalanceUnequalDoNot) {
  const Jaws equal(10.0, 10.0), unequal(10.0, 2.0);
  SqueezeBalanceOptions o;
  o.push_force = 0.0;
  const SqueezeBalanceResult a = squeezeBalance(equal.contacts, equal.drive, {0, 0, 0}, 0.05, o);
  EXPECT_TRUE(a.balanced);
  EXPECT_LT(a.squeeze_residual, 1e-9);
  const SqueezeBalanceResult b =
      squeezeBalance(unequal.contacts, unequal.drive, {0, 0, 0}, 0.05, o);
  // Normal forces s0, s1 minimising (s0 - s1)^2 (object) + (s0 - 10)^2 + (s1 - 2)^2 (jaws):
  // s0 = 22/3, s1 = 14/3, every term (8/3)^2; relative to |(10, 2)| (tangential edges only
  // add to the object's residual).
  EXPECT_NEAR(b.squeeze_residual, std::sqrt(64.0 / 3.0) / std::sqrt(104.0), 1e-6);
  EXPECT_FALSE(b.balanced);
}

TEST(SqueezeBalance, FrictionResistsASidewaysPushOnlyUnderAFirmSqueeze) {
  // Friction 0.6 on two contacts holds 2 x 0.6 x F sideways (a little less: the 8-edge cone
  // is inscribed); a 1 N push needs F well above 1 / 1.2 N.
  SqueezeBalanceOptions o;
  const Jaws firm(10.0, 10.0), weak(0.1, 0.1);
  const SqueezeBalanceResult a = squeezeBalance(firm.contacts, firm.drive, {0, 0, 0}, 0.05, o);
  EXPECT_TRUE(a.balanced) << a.push_residual;
  EXPECT_EQ(a.failed_push, -1);
  const SqueezeBalanceResult b = squeezeBalance(weak.contacts, weak.drive, {0, 0, 0}, 0.05, o);
  EXPECT_FALSE(b.balanced);
  EXPECT_GE(b.failed_push, 0);
  EXPECT_GT(b.push_residual, o.push_tolerance);
}

TEST(SqueezeBalance, RefusesMismatchedSizesAndBadOptions) {
  Jaws jaws(1.0, 1.0);
  jaws.drive.jacobians.pop_back();
  EXPECT_TRUE(testing::throwsError(
      [&] {
        squeezeBalance(jaws.contacts, jaws.drive, {0, 0, 0}, 0.05);
      },
      {"1 contact jacobians for 2 contacts", "one per contact"}));
  SqueezeBalanceOptions o;
  o.push_tolerance = 2.0;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"push_tolerance", "[0, 1]"}));
  o = SqueezeBalanceOptions{};
  o.cone_edges = 2;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"cone_edges", ">= 3"}));
}

}  // namespace
}  // namespace taskmap
