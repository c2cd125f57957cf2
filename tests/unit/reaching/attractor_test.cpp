// Attractor dynamics (eq. 1.17-1.19) against the continuous critically damped solution, and
// reaching rollouts: target reached in the default scene, clearance kept by the collision
// null-space term where the same rollout without it collides.
#include "taskmap/reaching/attractor.hpp"

#include <gtest/gtest.h>

#include <iostream>

#include <Eigen/SVD>

#include "reaching_fixtures.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/reaching/reach_scene.hpp"

namespace taskmap {
namespace {

TEST(Attractor, CoefficientsFollowEquation119) {
  AttractorOptions o;
  o.relaxation_time = 0.2;
  o.damping = 1.0;
  o.dt = 0.01;
  const AttractorCoefficients c = attractorCoefficients(o);
  const double denom = 0.04 + 2 * 0.2 * 0.01 + 0.0001;
  EXPECT_DOUBLE_EQ(c.a, 0.0001 / denom);
  EXPECT_DOUBLE_EQ(c.b, 0.04 / denom);
  o.dt = 0.0;
  EXPECT_THROW(attractorCoefficients(o), Error);
}

TEST(Attractor, StepResponseConvergesToTheCriticallyDampedSolution) {
  // T^2 x'' + 2 T xi x' + x = r with xi = 1 and a unit step: x(t) = 1 - (1 + t/T) e^{-t/T}.
  AttractorOptions o;
  o.relaxation_time = 0.3;
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(1), r = Eigen::VectorXd::Ones(1);
  double previous_error = 1.0;
  for (double dt : {1e-2, 1e-3, 1e-4}) {
    o.dt = dt;
    const int steps = static_cast<int>(std::round(1.5 / dt));
    // A segment time of one step makes the attractor point jump to r: a step input.
    const auto x = attractorTrajectory(o, x0, {r}, dt, steps);
    double error = 0.0;
    for (int k = 0; k <= steps; ++k) {
      const double t = k * dt, s = t / o.relaxation_time;
      error = std::max(error, std::abs(x[k][0] - (1.0 - (1.0 + s) * std::exp(-s))));
      if (k > 0) {
        EXPECT_GE(x[k][0], x[k - 1][0] - 1e-15);  // monotone: no overshoot
      }
      EXPECT_LE(x[k][0], 1.0 + 1e-12);
    }
    EXPECT_LT(error, 0.5 * previous_error);  // first-order convergence in dt
    previous_error = error;
  }
  EXPECT_LT(previous_error, 1e-3);
}

TEST(Attractor, UnderdampedOvershootsAndPointsAreInterpolated) {
  AttractorOptions o;
  o.damping = 0.3;
  const Eigen::VectorXd x0 = Eigen::VectorXd::Zero(2);
  const auto x = attractorTrajectory(o, x0, {Eigen::Vector2d(1, 0)}, 0.01, 300);
  double peak = 0;
  for (const auto& v : x) peak = std::max(peak, v[0]);
  EXPECT_GT(peak, 1.05);
  // Two attractor points: the trajectory passes near the first and ends at the second.
  o.damping = 1.0;
  const auto y =
      attractorTrajectory(o, x0, {Eigen::Vector2d(1, 0), Eigen::Vector2d(1, 1)}, 1.0, 600);
  EXPECT_NEAR(y.back()[0], 1.0, 1e-6);
  EXPECT_NEAR(y.back()[1], 1.0, 1e-6);
  EXPECT_GT(y[100][0], y[100][1]);  // first leg before the second
  EXPECT_THROW(attractorTrajectory(o, x0, {Eigen::Vector3d(1, 0, 0)}, 1.0, 10), Error);
}

TEST(Reach, PandaReachesASideGraspOfTheObjectWithoutCollision) {
  RobotModel robot = test::pandaInDefaultScene();
  const ReachScene scene = defaultReachScene();
  CollisionOptions co;
  co.hand_may_touch = {scene.object};
  const CollisionModel collisions(robot, co);
  const ReachResult r = reach(robot, &collisions, robot.palmBody(), robot.requireBody("object"),
                              test::sideGrasp(), test::readyPose(), ReachOptions{});
  std::cout << r.message << ": position error " << r.position_error << " m, orientation error "
            << r.orientation_error << " rad, min clearance " << r.min_clearance << " m ("
            << r.min_clearance_pair << "), joint margin " << r.joint_limit_margin << "\n";
  EXPECT_EQ(r.status, ReachStatus::kReached) << r.message;
  EXPECT_LT(r.position_error, 1e-3);
  EXPECT_GT(r.min_clearance, 0.0);
  EXPECT_GE(r.joint_limit_margin, 0.0);
  EXPECT_EQ(r.q.size(), 301u);
}

TEST(Reach, CollisionNullSpaceTermKeepsClearWhereTheSameRolloutWouldCollide) {
  RobotModel robot = test::pandaInDefaultScene();
  const ReachScene scene = defaultReachScene();
  // Plain rollout (collision gain 0): where is the elbow a third of the way?
  ReachOptions plain;
  plain.ik.collision_gain = 0.0;
  CollisionOptions co;
  co.hand_may_touch = {scene.object};
  const int object = robot.requireBody("object");
  const ReachResult free_run =
      reach(robot, nullptr, robot.palmBody(), object, test::sideGrasp(), test::readyPose(), plain);
  ASSERT_EQ(free_run.status, ReachStatus::kReached);
  // The elbow's self-motion direction at step 100 (along link 4's capsule axis): the null space of
  // the 6 x 7 palm Jacobian.
  const int step = 100;
  Kinematics kin(robot);
  kin.update(free_run.q[step]);
  const Eigen::MatrixXd j = kin.jacobian(robot.palmBody());
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(j, Eigen::ComputeFullV);
  const Eigen::VectorXd self_motion = svd.matrixV().col(6);
  const int link4 = robot.requireBody("fer_link4");
  const Eigen::Vector3d elbow = kin.pose(link4).translation();
  const Eigen::Vector3d swing = (kin.pointJacobian(link4, elbow) * self_motion).normalized();
  // A ball on the elbow's path, placed to one side of the self-motion circle: without the
  // collision term the elbow runs into it; with it the elbow swings away.
  const double offset = 0.12;  // link 4's capsule: half length 0.06, radius 0.06
  robot.addEnvironmentBody(
      "ball", Eigen::Isometry3d(Eigen::Translation3d(elbow + offset * swing)),
      {Primitive::capsule(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.04)});
  const CollisionModel collisions(robot, co);
  const ReachResult without = reach(robot, &collisions, robot.palmBody(), object, test::sideGrasp(),
                                    test::readyPose(), plain);
  const ReachOptions avoid;
  const ReachResult with = reach(robot, &collisions, robot.palmBody(), object, test::sideGrasp(),
                                 test::readyPose(), avoid);
  std::cout << "without: " << without.message << " clearance " << without.min_clearance
            << "\nwith: " << with.message << " clearance " << with.min_clearance << " ("
            << with.min_clearance_pair << ") position error " << with.position_error << "\n";
  EXPECT_EQ(without.status, ReachStatus::kCollided);
  EXPECT_LT(without.min_clearance, -0.02);
  EXPECT_EQ(with.status, ReachStatus::kReached) << with.message;
  EXPECT_GT(with.min_clearance, 0.0);
}

TEST(Reach, ViaPointBendsThePathAndTheTargetIsStillReached) {
  RobotModel robot = test::pandaInDefaultScene();
  const ReachScene scene = defaultReachScene();
  CollisionOptions co;
  co.hand_may_touch = {scene.object};
  const CollisionModel collisions(robot, co);
  const int object = robot.requireBody(scene.object);
  Eigen::Isometry3d via = test::sideGrasp();
  via.translation() += Eigen::Vector3d(0.0, -0.25, 0.1);
  const auto closest = [&](const ReachResult& r) {
    double best = 1e9;
    for (const Eigen::Isometry3d& p : r.palm)
      best = std::min(best, (p.translation() - via.translation()).norm());
    return best;
  };
  ReachOptions options;
  const ReachResult direct = reach(robot, &collisions, robot.palmBody(), object, test::sideGrasp(),
                                   test::readyPose(), options);
  options.via_points = {via};
  options.move_time = 2.0;
  options.steps = 400;  // 2 s of motion, 2 s to settle
  const ReachResult bent = reach(robot, &collisions, robot.palmBody(), object, test::sideGrasp(),
                                 test::readyPose(), options);
  std::cout << "closest approach to the via point: direct " << closest(direct) << " m, with via "
            << closest(bent) << " m\n";
  EXPECT_EQ(bent.status, ReachStatus::kReached) << bent.message;
  EXPECT_LT(closest(bent), 0.05);
  EXPECT_GT(closest(direct), 0.1);
}

TEST(Attractor, AttractorPointInterpolatesLinearly) {
  const Eigen::VectorXd x0 = Eigen::Vector2d(0, 0);
  const std::vector<Eigen::VectorXd> pts = {Eigen::Vector2d(1, 0), Eigen::Vector2d(1, 2)};
  EXPECT_TRUE(attractorPoint(x0, pts, 0.5, 0.25).isApprox(Eigen::Vector2d(0.5, 0)));
  EXPECT_TRUE(attractorPoint(x0, pts, 0.5, 0.75).isApprox(Eigen::Vector2d(1, 1)));
  EXPECT_TRUE(attractorPoint(x0, pts, 0.5, 5.0).isApprox(Eigen::Vector2d(1, 2)));
}

}  // namespace
}  // namespace taskmap
