// Collision pairs and the collision cost (eq. 1.9-1.16): zone functions, gradient against
// central finite differences, robustness where the cores touch.
#include "taskmap/reaching/collision_model.hpp"

#include <gtest/gtest.h>

#include "reaching_fixtures.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/reaching/reach_scene.hpp"

namespace taskmap {
namespace {

RobotModel pandaInScene() {
  RobotModel robot = test::pandaWithHand();
  addSceneTo(defaultReachScene(), robot);
  // Extra obstacles around the workspace so that many pairs fall in every zone.
  robot.addEnvironmentBody("pole", Eigen::Isometry3d(Eigen::Translation3d(0.35, -0.25, 0.0)),
                           {Primitive::capsule({0, 0, 0}, {0, 0, 0.8}, 0.04)});
  Eigen::Isometry3d shelf = Eigen::Isometry3d::Identity();
  shelf.translation() = Eigen::Vector3d(0.0, 0.45, 0.5);
  robot.addEnvironmentBody("shelf", shelf,
                           {Primitive::fromBox(Eigen::Isometry3d::Identity(), {0.6, 0.3, 0.03})});
  return robot;
}

TEST(CollisionModel, PairSelectionFollowsTheOptions) {
  const RobotModel robot = pandaInScene();
  CollisionOptions options;
  options.hand_may_touch = {"object"};
  const CollisionModel model(robot, options);
  const auto& bodies = robot.bodies();
  int self = 0;
  for (const CollisionPair& p : model.pairs()) {
    EXPECT_NE(bodies[p.body_a].role, BodyRole::kEnvironment);
    if (bodies[p.body_b].role == BodyRole::kEnvironment) {
      EXPECT_GE(bodies[p.body_a].chain_depth, 2);
      EXPECT_FALSE(bodies[p.body_a].role == BodyRole::kHand && bodies[p.body_b].name == "object");
    } else {
      ++self;
      EXPECT_GE(std::abs(bodies[p.body_a].chain_depth - bodies[p.body_b].chain_depth), 3);
    }
  }
  EXPECT_GT(self, 0);
  CollisionOptions no_self = options;
  no_self.self_collision = false;
  EXPECT_EQ(CollisionModel(robot, no_self).pairs().size() + self, model.pairs().size());
}

TEST(CollisionModel, ZoneFunctionsAreContinuousWithMatchingDerivatives) {
  const RobotModel robot = pandaInScene();
  CollisionOptions options;
  options.boundary_distance = 0.08;
  options.slope = 3.0;
  options.center_weight = 0.5;
  const CollisionModel model(robot, options);
  const double db = options.boundary_distance;
  // Continuity at the zone borders.
  EXPECT_NEAR(model.closestPointCost(-1e-12, nullptr), model.closestPointCost(1e-12, nullptr),
              1e-10);
  EXPECT_NEAR(model.closestPointCost(db - 1e-12, nullptr), 0.0, 1e-10);
  EXPECT_NEAR(model.closestPointCost(0.0, nullptr), 3.0 * db * db, 1e-15);
  EXPECT_NEAR(model.closestPointCost(-0.01, nullptr), 3.0 * db * (db + 0.02), 1e-15);
  EXPECT_NEAR(model.centerPointCost(db - 1e-12, 0.1, nullptr, nullptr), 0.0, 1e-10);
  EXPECT_NEAR(model.centerPointCost(-0.01, 0.1, nullptr, nullptr), 0.5 * std::exp(-0.1), 1e-15);
  // Derivatives against central differences inside each zone.
  const double h = 1e-7;
  for (double d : {-0.03, 0.01, 0.05, 0.1}) {
    double deriv = 0.0;
    model.closestPointCost(d, &deriv);
    const double fd =
        (model.closestPointCost(d + h, nullptr) - model.closestPointCost(d - h, nullptr)) / (2 * h);
    EXPECT_NEAR(deriv, fd, 1e-7 * std::max(1.0, std::abs(fd))) << d;
    double ddp = 0.0, ddc = 0.0;
    model.centerPointCost(d, 0.2, &ddp, &ddc);
    EXPECT_NEAR(ddp,
                (model.centerPointCost(d + h, 0.2, nullptr, nullptr) -
                 model.centerPointCost(d - h, 0.2, nullptr, nullptr)) /
                    (2 * h),
                1e-7);
    EXPECT_NEAR(ddc,
                (model.centerPointCost(d, 0.2 + h, nullptr, nullptr) -
                 model.centerPointCost(d, 0.2 - h, nullptr, nullptr)) /
                    (2 * h),
                1e-7);
  }
}

/// True when every pair is at least `margin` away from the zone borders (kinks of eq. 1.9)
/// and no cores touch.
bool awayFromKinks(const CollisionModel& model, const Kinematics& kin, double margin) {
  const double db = model.options().boundary_distance;
  for (const PairDistance& d : model.distances(kin)) {
    const double dp = d.closest.distance;
    if (std::abs(dp) < margin || std::abs(dp - db) < margin || d.closest.cores_touch) return false;
  }
  return true;
}

TEST(CollisionModel, GradientMatchesFiniteDifferences) {
  const RobotModel robot = pandaInScene();
  CollisionOptions options;
  options.boundary_distance = 0.1;
  const CollisionModel model(robot, options);
  Kinematics kin(robot);
  std::mt19937 rng(31);
  int checked = 0, penetrating = 0, parabolic = 0;
  for (int s = 0; s < 400 && checked < 40; ++s) {
    const Eigen::VectorXd q = test::randomConfiguration(robot, rng);
    kin.update(q);
    if (!awayFromKinks(model, kin, 1e-4)) continue;
    Eigen::VectorXd g;
    const double h0 = model.cost(kin, &g);
    if (h0 == 0.0) continue;
    for (const PairDistance& d : model.distances(kin)) {
      penetrating += d.closest.distance < 0.0;
      parabolic += d.closest.distance > 0.0 && d.closest.distance < options.boundary_distance;
    }
    Eigen::VectorXd fd(q.size());
    const double step = 1e-6;
    for (int i = 0; i < q.size(); ++i) {
      Eigen::VectorXd qp = q, qm = q;
      qp[i] += step;
      qm[i] -= step;
      kin.update(qp);
      const double hp = model.cost(kin, nullptr);
      kin.update(qm);
      fd[i] = (hp - model.cost(kin, nullptr)) / (2 * step);
    }
    EXPECT_LT((g - fd).norm(), 1e-6 * std::max(1e-3, fd.norm()))
        << "sample " << s << "\nanalytic " << g.transpose() << "\nfd       " << fd.transpose();
    ++checked;
  }
  EXPECT_GE(checked, 20);
  EXPECT_GT(penetrating, 0);
  EXPECT_GT(parabolic, 0);
}

TEST(CollisionModel, CostAgreesWithDistancesAndCullingIsExact) {
  const RobotModel robot = pandaInScene();
  const CollisionModel model(robot, CollisionOptions{});
  Kinematics kin(robot);
  std::mt19937 rng(32);
  for (int s = 0; s < 20; ++s) {
    kin.update(test::randomConfiguration(robot, rng));
    double expected = 0.0;
    for (const PairDistance& d : model.distances(kin))
      expected += model.closestPointCost(d.closest.distance, nullptr) +
                  model.centerPointCost(d.closest.distance, d.center_distance, nullptr, nullptr);
    EXPECT_NEAR(model.cost(kin, nullptr), expected, 1e-12);
  }
}

TEST(CollisionModel, GradientIsFiniteWhereCoresTouch) {
  RobotModel robot = test::pandaWithHand();
  // A rod through the middle of the upper arm (link 3's capsule axis) at a configuration q.
  Eigen::VectorXd q(7);
  q << 0.4, -0.3, 0.2, -2.0, 0.1, 1.8, 0.3;
  Kinematics at_q(robot);
  at_q.update(q);
  const int link3 = robot.requireBody("fer_link3");
  const Eigen::Vector3d c = at_q.pose(link3) * Eigen::Vector3d(0, 0, -0.145);
  const Eigen::Vector3d dir = Eigen::Vector3d(0.3, 0.5, 0.8).normalized() * 0.2;
  robot.addEnvironmentBody("rod", Eigen::Isometry3d(Eigen::Translation3d(c)),
                           {Primitive::capsule(-dir, dir, 0.01)});
  const CollisionModel model(robot, CollisionOptions{});
  Kinematics kin(robot);
  kin.update(q);
  int pair = -1;
  EXPECT_LT(model.minimumDistance(kin, &pair), -0.06);
  EXPECT_TRUE(model.distances(kin)[pair].closest.cores_touch) << model.pairName(pair);
  Eigen::VectorXd g;
  EXPECT_GT(model.cost(kin, &g), 0.0);
  EXPECT_TRUE(g.allFinite());
  EXPECT_GT(g.norm(), 0.0);
}

TEST(CollisionModel, InvalidOptionsAreRejected) {
  const RobotModel robot = pandaInScene();
  CollisionOptions o;
  o.boundary_distance = 0.0;
  EXPECT_THROW(CollisionModel(robot, o), Error);
  o = CollisionOptions{};
  o.hand_may_touch = {"cup"};
  EXPECT_THROW(CollisionModel(robot, o), Error);
}

}  // namespace
}  // namespace taskmap
