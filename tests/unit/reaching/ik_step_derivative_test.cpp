// Reverse-mode derivative of one reaching step (docs/REACHING.md T3) against central finite
// differences of lambda^T F(q, x, x_next): a free step, a step scaled to the velocity limits, a
// step with a locked joint, steps with the collision null-space term active; bad IK set-ups are
// refused with a message.
#include "taskmap/reaching/ik_step_derivative.hpp"

#include <gtest/gtest.h>

#include <iostream>
#include <memory>

#include "reaching_fixtures.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/reaching/reach_scene.hpp"

namespace taskmap {
namespace {

struct StepFixture {
  RobotModel robot = test::pandaInDefaultScene();
  std::unique_ptr<CollisionModel> collisions;
  std::unique_ptr<ResolvedRateIK> ik;
  int palm = -1, object = -1;
  Eigen::Matrix3d frame = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).matrix();
  double dt = 0.01;

  explicit StepFixture(double boundary_distance) {
    const ReachScene scene = defaultReachScene();
    CollisionOptions co;
    co.hand_may_touch = {scene.object};
    co.boundary_distance = boundary_distance;
    collisions = std::make_unique<CollisionModel>(robot, co);
    palm = robot.palmBody();
    object = robot.requireBody(scene.object);
    ik = std::make_unique<ResolvedRateIK>(
        robot,
        std::vector<TaskSpec>{{TaskKind::kPosition, palm, object, -1},
                              {TaskKind::kOrientation, palm, object, -1}},
        collisions.get(), IkOptions{});
  }

  /// Task variables of the palm at q (relative to frame).
  Eigen::VectorXd taskAt(const Eigen::VectorXd& q) const {
    Kinematics kin(robot);
    kin.update(q);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = kin.relativePosition(palm, object);
    pose.linear() = kin.relativeRotation(palm, object);
    return taskVariables(pose, frame);
  }

  /// Largest relative error of the three analytic products against central differences;
  /// returns the trace of the step for the caller's checks.
  IkStepTrace check(const Eigen::VectorXd& q, const Eigen::VectorXd& x,
                    const Eigen::VectorXd& x_next, const char* label, double* error) const {
    Kinematics kin(robot);
    kin.update(q);
    IkStepTrace trace;
    reachStep(*ik, kin, frame, dt, x, x_next, &trace);
    std::mt19937 rng(11);
    std::normal_distribution<double> normal;
    Eigen::VectorXd lambda(robot.dofs());
    for (int i = 0; i < lambda.size(); ++i) lambda[i] = normal(rng);
    ReachStepDerivative derivative(*ik, frame, dt);
    const ReachStepAdjoint a = derivative.vectorJacobian(kin, x, x_next, trace, lambda);
    // Fourth-order central differences: the feed-forward term divides by dt, so the step's
    // second derivatives are large and second-order differences are too coarse at any h.
    const double h = 3e-6;
    const auto projected = [&](const Eigen::VectorXd& qq, const Eigen::VectorXd& xx,
                               const Eigen::VectorXd& nn) {
      Kinematics k(robot);
      k.update(qq);
      return lambda.dot(reachStep(*ik, k, frame, dt, xx, nn));
    };
    // d/ds lambda^T F(inputs + s e_i) at s = 0 for input block `which` (0 q, 1 x, 2 x_next).
    const auto difference = [&](int which, int i) {
      const auto at = [&](double s) {
        Eigen::VectorXd qq = q, xx = x, nn = x_next;
        (which == 0 ? qq : which == 1 ? xx : nn)[i] += s;
        return projected(qq, xx, nn);
      };
      return (8.0 * (at(h) - at(-h)) - (at(2 * h) - at(-2 * h))) / (12.0 * h);
    };
    Eigen::VectorXd fd_q(robot.dofs()), fd_x(6), fd_n(6);
    for (int i = 0; i < robot.dofs(); ++i) fd_q[i] = difference(0, i);
    for (int i = 0; i < 6; ++i) {
      fd_x[i] = difference(1, i);
      fd_n[i] = difference(2, i);
    }
    const auto rel = [](const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
      return (u - v).norm() / std::max(1e-3, v.norm());
    };
    *error = std::max({rel(a.q, fd_q), rel(a.x, fd_x), rel(a.x_next, fd_n)});
    std::cout << label << ": relative error q " << rel(a.q, fd_q) << ", x " << rel(a.x, fd_x)
              << ", x_next " << rel(a.x_next, fd_n) << " (scale " << trace.scale << ")\n";
    return trace;
  }
};

TEST(ReachStepDerivative, MatchesCentralDifferencesOnRandomSteps) {
  const StepFixture f(0.05);
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  for (int s = 0; s < 5; ++s) {
    const Eigen::VectorXd q = test::randomConfiguration(f.robot, rng, 0.1);
    Eigen::VectorXd x = f.taskAt(q), step(6);
    for (int i = 0; i < 6; ++i) {
      x[i] += 0.02 * normal(rng);
      step[i] = 0.002 * normal(rng);
    }
    double error = 0.0;
    const IkStepTrace t = f.check(q, x, x + step, "random step", &error);
    EXPECT_LT(error, 1e-6);
  }
}

TEST(ReachStepDerivative, HoldsTheVelocityScalingJoint) {
  const StepFixture f(0.05);
  const Eigen::VectorXd q = test::readyPose();
  Eigen::VectorXd x = f.taskAt(q), x_next = x;
  x_next.head<3>() += Eigen::Vector3d(0.05, -0.04, 0.03);  // 5 m/s feed-forward
  x_next.tail<3>() += Eigen::Vector3d(0.02, 0.01, -0.03);
  double error = 0.0;
  const IkStepTrace t = f.check(q, x, x_next, "scaled step", &error);
  EXPECT_GT(t.scale, 1.5);
  EXPECT_GE(t.scale_joint, 0);
  EXPECT_LT(error, 1e-6);
}

TEST(ReachStepDerivative, HoldsLockedJoints) {
  const StepFixture f(0.05);
  // Joint 3 (the elbow) just inside its upper limit, the goal pulling the palm to fold it more.
  Eigen::VectorXd q = test::readyPose();
  q[3] = f.robot.upper()[3] - 1e-3;
  Eigen::VectorXd x = f.taskAt(q), x_next = x;
  bool locked = false;
  double error = 0.0;
  for (int i = 0; i < 6 && !locked; ++i) {
    for (double sign : {1.0, -1.0}) {
      Eigen::VectorXd n = x;
      n[i] += sign * 0.01;
      Kinematics kin(f.robot);
      kin.update(q);
      IkStepTrace t;
      reachStep(*f.ik, kin, f.frame, f.dt, x, n, &t);
      if (t.locked[3]) {
        x_next = n;
        locked = true;
        break;
      }
    }
  }
  ASSERT_TRUE(locked) << "no goal direction locks the elbow";
  const IkStepTrace t = f.check(q, x, x_next, "locked elbow", &error);
  EXPECT_TRUE(t.locked[3]);
  EXPECT_LT(error, 1e-6);
}

TEST(ReachStepDerivative, MatchesWithTheCollisionGradientActive) {
  // Boundary 0.3 m: many pairs in the parabolic zone, the collision Hessian in the products.
  const StepFixture f(0.3);
  std::mt19937 rng(9);
  std::normal_distribution<double> normal;
  int active = 0;
  for (int s = 0; s < 4; ++s) {
    const Eigen::VectorXd q = test::randomConfiguration(f.robot, rng, 0.1);
    Kinematics kin(f.robot);
    kin.update(q);
    if (f.collisions->cost(kin, nullptr) > 0.0) ++active;
    Eigen::VectorXd x = f.taskAt(q), step(6);
    for (int i = 0; i < 6; ++i) step[i] = 0.002 * normal(rng);
    double error = 0.0;
    f.check(q, x, x + step, "collision step", &error);
    EXPECT_LT(error, 1e-6);
  }
  EXPECT_GE(active, 3);
}

TEST(ReachStepDerivative, RefusesOtherTaskStacks) {
  const StepFixture f(0.05);
  const ResolvedRateIK position_only(f.robot, {{TaskKind::kPosition, f.palm, f.object, -1}},
                                     nullptr, IkOptions{});
  try {
    ReachStepDerivative d(position_only, f.frame, f.dt);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("reachStep's tasks"), std::string::npos);
  }
  const int link = f.robot.requireBody("fer_link3");
  const ResolvedRateIK moving(
      f.robot,
      {{TaskKind::kPosition, f.palm, link, -1}, {TaskKind::kOrientation, f.palm, link, -1}},
      nullptr, IkOptions{});
  EXPECT_THROW(ReachStepDerivative(moving, f.frame, f.dt), Error);
}

}  // namespace
}  // namespace taskmap
