// Trajectory optimisation over attractor points (section 1.5): the gradient of the whole cost
// (path length, end velocity, collisions, joint limits, a terminal cost) with respect to the
// attractor points against central finite differences of complete rollouts; the descent lowers
// the cost; invalid input is refused with a message.
#include "taskmap/reaching/trajectory_optimizer.hpp"

#include <gtest/gtest.h>

#include <iostream>
#include <memory>

#include "reaching_fixtures.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/reaching/reach_scene.hpp"

namespace taskmap {
namespace {

struct Fixture {
  RobotModel robot = test::pandaInDefaultScene();
  ReachScene scene = defaultReachScene();
  CollisionModel* collisions = nullptr;
  std::unique_ptr<CollisionModel> owned;
  TrajectoryProblem problem;
  std::vector<Eigen::VectorXd> points;

  explicit Fixture(int steps) {
    CollisionOptions co;
    co.hand_may_touch = {scene.object};
    co.boundary_distance = 0.3;  // pairs inside the cost's range along the path
    owned = std::make_unique<CollisionModel>(robot, co);
    problem.robot = &robot;
    problem.collisions = owned.get();
    problem.body = robot.palmBody();
    problem.reference = robot.requireBody("object");
    problem.q0 = test::readyPose();
    problem.frame = test::sideGrasp().linear();
    problem.reach.steps = steps;
    problem.reach.move_time = 0.4;
    problem.weights.collision = 10.0;
    const Eigen::Vector3d goal =
        test::sideGrasp().translation() + Eigen::Vector3d(-0.05, 0.0, 0.03);
    const int palm = problem.body, object = problem.reference;
    problem.terminal = [goal, palm, object](const Kinematics& kin, Eigen::VectorXd* g) {
      const Eigen::Vector3d e = kin.relativePosition(palm, object) - goal;
      if (g) *g = 20.0 * kin.relativePositionJacobian(palm, object).transpose() * e;
      return 10.0 * e.squaredNorm();
    };
    const Eigen::Matrix<double, 6, 1> x0 = startTaskVariables(problem);
    Eigen::Matrix<double, 6, 1> target = Eigen::Matrix<double, 6, 1>::Zero();
    target.head<3>() = test::sideGrasp().translation();
    Eigen::Matrix<double, 6, 1> via = 0.5 * (x0 + target);
    via[2] += 0.05;
    points = {via, target};
  }
};

TEST(TrajectoryOptimizer, GradientMatchesCentralDifferencesOfWholeRollouts) {
  Fixture f(60);
  const TrajectoryCost c = evaluateTrajectory(f.problem, f.points, true);
  std::cout << "cost " << c.total << " (path " << c.path_length << ", end velocity "
            << c.end_velocity << ", collision " << c.collision << ", joint limit " << c.joint_limit
            << ", terminal " << c.terminal << ")\n";
  ASSERT_EQ(c.gradient.size(), 12);
  EXPECT_GT(c.collision, 0.0);  // the collision term is active, so its chain is checked too
  EXPECT_GT(c.terminal, 0.0);
  Eigen::VectorXd fd(12);
  const double h = 1e-5;
  for (int i = 0; i < 12; ++i) {
    std::vector<Eigen::VectorXd> plus = f.points, minus = f.points;
    plus[i / 6][i % 6] += h;
    minus[i / 6][i % 6] -= h;
    fd[i] = (evaluateTrajectory(f.problem, plus, false).total -
             evaluateTrajectory(f.problem, minus, false).total) /
            (2.0 * h);
  }
  const double rel = (c.gradient - fd).norm() / fd.norm();
  std::cout << "gradient " << c.gradient.transpose() << "\nfinite d " << fd.transpose()
            << "\nrelative error " << rel << "\n";
  EXPECT_LT(rel, 1e-5);
  // The oracle path (central differences of lambda^T F per IK step) agrees as well, and with the
  // analytic products to far below the tolerance.
  f.problem.step_derivative = StepDerivative::kFiniteDifferences;
  const TrajectoryCost oracle = evaluateTrajectory(f.problem, f.points, true);
  const double rel_oracle = (oracle.gradient - fd).norm() / fd.norm();
  const double rel_paths = (oracle.gradient - c.gradient).norm() / oracle.gradient.norm();
  std::cout << "finite-difference step products: relative error " << rel_oracle
            << ", analytic vs finite-difference products " << rel_paths << "\n";
  EXPECT_LT(rel_oracle, 1e-5);
  EXPECT_LT(rel_paths, 1e-6);
  // Forward differences for the step Jacobians: half the cost, error O(eps) plus round-off,
  // 7e-6 here at eps = 1e-8: near the 1e-5 bound, so the default stays central.
  f.problem.step_jacobian_differences = FiniteDifferences::kForward;
  f.problem.step_jacobian_epsilon = 1e-8;
  const TrajectoryCost forward = evaluateTrajectory(f.problem, f.points, true);
  const double rel_forward = (forward.gradient - fd).norm() / fd.norm();
  std::cout << "forward-difference step Jacobians: relative error " << rel_forward << "\n";
  EXPECT_LT(rel_forward, 2e-5);
}

TEST(TrajectoryOptimizer, DescentLowersTheCostMonotonically) {
  Fixture f(60);
  TrajectoryOptimizerOptions o;
  o.max_iterations = 8;
  int calls = 0;
  o.on_iteration = [&calls](int, const TrajectoryCost&) { ++calls; };
  const TrajectoryOptimization r = optimizeTrajectory(f.problem, f.points, o);
  ASSERT_GE(r.iterations, 1);
  EXPECT_EQ(calls, r.iterations + 1);
  ASSERT_EQ(r.history.size(), static_cast<std::size_t>(r.iterations) + 1);
  for (std::size_t i = 1; i < r.history.size(); ++i)
    EXPECT_LT(r.history[i].total, r.history[i - 1].total);
  EXPECT_LT(r.cost.total, 0.7 * r.history.front().total) << r.message;
  EXPECT_EQ(r.cost.q.size(), 61u);
}

TEST(TrajectoryOptimizer, RefusesInvalidInputWithAMessage) {
  Fixture f(10);
  try {
    evaluateTrajectory(f.problem, {}, false);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("attractor point"), std::string::npos);
  }
  f.problem.weights.path_length = -1.0;
  try {
    evaluateTrajectory(f.problem, f.points, false);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("path_length"), std::string::npos);
  }
  f.problem.weights.path_length = 1.0;
  f.problem.q0[0] = 10.0;
  EXPECT_THROW(evaluateTrajectory(f.problem, f.points, false), Error);
  f.problem.q0 = test::readyPose();
  f.problem.reference = f.robot.requireBody("fer_link3");  // moves with the joints
  try {
    evaluateTrajectory(f.problem, f.points, true);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("kFiniteDifferences"), std::string::npos);
  }
  f.problem.reference = f.robot.requireBody("object");
  TrajectoryOptimizerOptions o;
  o.max_iterations = 0;
  EXPECT_THROW(optimizeTrajectory(f.problem, f.points, o), Error);
}

}  // namespace
}  // namespace taskmap
