// BFGS on the attractor points (trajectory_bfgs.hpp): monotone descent with the same history
// contract as optimizeTrajectory; on a stiff terminal cost (a palm goal weighted like the map's
// proximity) it gets lower than the normalised-gradient descent in the same number of
// iterations; invalid options are refused.
#include "taskmap/reaching/trajectory_bfgs.hpp"

#include <gtest/gtest.h>

#include <iostream>

#include "reaching_fixtures.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

/// Panda with the humanoid hand, no scene: reach a palm position 1000 |p - goal|^2 (world frame).
struct StiffGoal {
  const RobotModel& robot = test::pandaWithHand();
  TrajectoryProblem problem;
  std::vector<Eigen::VectorXd> points;

  StiffGoal() {
    problem.robot = &robot;
    problem.body = robot.palmBody();
    problem.q0.resize(7);
    problem.q0 << 0.0, -M_PI / 4, 0.0, -3 * M_PI / 4, 0.0, M_PI / 2, M_PI / 4;
    problem.reach.steps = 40;
    problem.reach.move_time = 0.3;
    const Eigen::Matrix<double, 6, 1> x0 = startTaskVariables(problem);
    const Eigen::Vector3d goal = x0.head<3>() + Eigen::Vector3d(0.1, 0.15, -0.1);
    const int palm = problem.body;
    problem.terminal = [goal, palm](const Kinematics& kin, Eigen::VectorXd* g) {
      const Eigen::Vector3d e = kin.relativePosition(palm, -1) - goal;
      if (g) *g = 2000.0 * kin.relativePositionJacobian(palm, -1).transpose() * e;
      return 1000.0 * e.squaredNorm();
    };
    Eigen::Matrix<double, 6, 1> target = x0;
    target.head<3>() += Eigen::Vector3d(0.05, 0.05, 0.0);  // 0.16 m short of the goal
    points = {0.5 * (x0 + target), target};
  }
};

TEST(TrajectoryBfgs, DescendsMonotonicallyAndBeatsTheGradientDescent) {
  StiffGoal f;
  TrajectoryOptimizerOptions o;
  o.max_iterations = 10;
  o.relative_tolerance = 0.0;
  int calls = 0;
  o.on_iteration = [&calls](int, const TrajectoryCost&) { ++calls; };
  const TrajectoryOptimization b = optimizeTrajectoryBfgs(f.problem, f.points, o);
  ASSERT_GE(b.iterations, 1);
  EXPECT_EQ(calls, b.iterations + 1);
  ASSERT_EQ(b.history.size(), static_cast<std::size_t>(b.iterations) + 1);
  for (std::size_t i = 1; i < b.history.size(); ++i)
    EXPECT_LT(b.history[i].total, b.history[i - 1].total);
  EXPECT_EQ(b.cost.q.size(), 41u);
  EXPECT_EQ(b.points.size(), 2u);
  const TrajectoryOptimization g = optimizeTrajectory(f.problem, f.points, o);
  std::cout << "start " << b.history.front().total << ", after " << o.max_iterations
            << " iterations: BFGS " << b.cost.total << " (" << b.iterations
            << " iterations), gradient descent " << g.cost.total << " (" << g.iterations << ")\n";
  EXPECT_LT(b.cost.total, g.cost.total);
  EXPECT_LT(b.cost.total, 0.1 * b.history.front().total);
}

TEST(TrajectoryBfgs, RefusesInvalidOptions) {
  StiffGoal f;
  TrajectoryOptimizerOptions o;
  o.initial_step = 0.0;
  try {
    optimizeTrajectoryBfgs(f.problem, f.points, o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("initial_step"), std::string::npos) << e.what();
  }
  EXPECT_THROW(optimizeTrajectoryBfgs(f.problem, {}, TrajectoryOptimizerOptions{}), Error);
}

}  // namespace
}  // namespace taskmap
