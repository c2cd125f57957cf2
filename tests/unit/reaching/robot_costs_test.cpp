// End-state comfort costs of a robot posture (eq. 1.8-1.10): formula, finite differences,
// continuity, errors; the reaching stage's own costs are these.
#include "taskmap/reaching/robot_costs.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

TEST(JointLimitCost, MatchesFormulaAndGradient) {
  Eigen::VectorXd lo(3), hi(3), q(3);
  lo << -1, 0, -2;
  hi << 1, 2, 0;
  q << 0.5, 2, -2;
  // 1/2 ((0.5 - 0) / 2)^2 + 1/2 ((2 - 1) / 2)^2 + 1/2 ((-2 + 1) / 2)^2
  Eigen::VectorXd g;
  EXPECT_DOUBLE_EQ(jointLimitCost(q, lo, hi, &g), 0.5 * (0.0625 + 0.25 + 0.25));
  for (int i = 0; i < 3; ++i) {
    Eigen::VectorXd a = q, b = q;
    a[i] += 1e-6;
    b[i] -= 1e-6;
    EXPECT_NEAR(g[i], (jointLimitCost(a, lo, hi) - jointLimitCost(b, lo, hi)) / 2e-6, 1e-8);
  }
  EXPECT_DOUBLE_EQ(jointLimitCost(Eigen::Vector3d(0, 1, -1), lo, hi), 0.0);
  EXPECT_EQ(testing::errorMessage([&] { jointLimitCost(q, hi, lo); }),
            "joint limits of joint 0: need finite lower < upper");
}

TEST(CollisionCost, PiecewiseFormulaIsC1) {
  const double zone = 0.05, s = 2.0;
  EXPECT_DOUBLE_EQ(collisionPairCost(0.06, zone, s), 0.0);
  EXPECT_DOUBLE_EQ(collisionPairCost(0.02, zone, s), s * 0.03 * 0.03);
  EXPECT_DOUBLE_EQ(collisionPairCost(-0.01, zone, s), s * zone * (zone + 0.02));
  for (double d : {-1e-12, 1e-12, zone - 1e-12, zone + 1e-12}) {  // continuity at 0 and d_B
    const double a = d < 0 || (d > 0 && d < 0.01) ? 0.0 : zone;
    EXPECT_NEAR(collisionPairCost(d, zone, s), collisionPairCost(a, zone, s), 1e-10);
  }
  double d_minus = 0, d_plus = 0;
  collisionPairCost(-1e-9, zone, s, &d_minus);
  collisionPairCost(1e-9, zone, s, &d_plus);
  EXPECT_NEAR(d_minus, d_plus, 1e-7);  // slope continuous at contact
  EXPECT_DOUBLE_EQ(collisionCost({0.06, 0.02, -0.01}, zone, s),
                   collisionPairCost(0.02, zone, s) + collisionPairCost(-0.01, zone, s));
}

TEST(MakeComfort, SumsJointLimitAndWeightedCollisionCosts) {
  const Eigen::Vector2d lo(-1, 0), hi(1, 2), q(0.5, 0.5);
  const auto distances = [](const Eigen::VectorXd& x) {
    return std::vector<double>{x[0] - 0.52, 0.2};
  };
  const ComfortFunction c = makeComfort(lo, hi, distances, 0.05, 2.0, 3.0);
  EXPECT_DOUBLE_EQ(c(q),
                   jointLimitCost(q, lo, hi) + 3.0 * collisionCost({q[0] - 0.52, 0.2}, 0.05, 2.0));
  EXPECT_DOUBLE_EQ(makeComfort(lo, hi)(q), jointLimitCost(q, lo, hi));
  EXPECT_EQ(testing::errorMessage([&] { makeComfort(lo, hi, distances, 0.0); }),
            "comfort: zone distance must be > 0 (metres)");
}

}  // namespace
}  // namespace taskmap
