// Resolved-rate IK (eq. 1.1-1.2, 1.8): task tracking, weighted minimum norm, null-space
// projection, joint-limit gradient, convergence from random starts.
#include "taskmap/reaching/resolved_rate_ik.hpp"

#include <gtest/gtest.h>

#include <iostream>

#include "reaching_fixtures.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/pose.hpp"

namespace taskmap {
namespace {

std::vector<TaskSpec> palmPoseTasks(const RobotModel& robot, int reference = -1) {
  return {{TaskKind::kPosition, robot.palmBody(), reference, -1},
          {TaskKind::kOrientation, robot.palmBody(), reference, -1}};
}

std::vector<TaskGoal> goalsAt(const Kinematics& kin, int body, int reference) {
  std::vector<TaskGoal> g(2);
  g[0].position = kin.relativePosition(body, reference);
  g[1].rotation = kin.relativeRotation(body, reference);
  return g;
}

TEST(ResolvedRateIK, JointLimitGradientMatchesFiniteDifferences) {
  const RobotModel& robot = test::pandaWithHand();
  std::mt19937 rng(41);
  const Eigen::VectorXd q = test::randomConfiguration(robot, rng);
  Eigen::VectorXd g;
  jointLimitCost(robot, q, &g);
  for (int i = 0; i < q.size(); ++i) {
    Eigen::VectorXd qp = q, qm = q;
    qp[i] += 1e-6;
    qm[i] -= 1e-6;
    const double fd =
        (jointLimitCost(robot, qp, nullptr) - jointLimitCost(robot, qm, nullptr)) / 2e-6;
    EXPECT_NEAR(g[i], fd, 1e-6 * std::max(1.0, std::abs(fd)));
  }
  EXPECT_DOUBLE_EQ(jointLimitCost(robot, robot.midConfiguration(), nullptr), 0.0);
}

TEST(ResolvedRateIK, TaskIsTrackedExactlyAndTheNullSpaceTermDescendsTheCost) {
  const RobotModel& robot = test::pandaWithHand();
  IkOptions options;
  options.damping = 0.0;
  const ResolvedRateIK ik(robot, palmPoseTasks(robot), nullptr, options);
  Kinematics kin(robot);
  std::mt19937 rng(42);
  for (int s = 0; s < 20; ++s) {
    kin.update(test::randomConfiguration(robot, rng, 0.1));
    std::vector<TaskGoal> goals = goalsAt(kin, robot.palmBody(), -1);
    goals[0].position += Eigen::Vector3d(0.01, -0.02, 0.005);
    goals[0].velocity = Eigen::Vector3d(0.1, 0.0, -0.2);
    goals[1].velocity = Eigen::Vector3d(0.0, 0.3, 0.1);
    const IkVelocity v = ik.velocity(kin, goals);
    Eigen::VectorXd e;
    Eigen::MatrixXd j;
    ik.taskError(kin, goals, e, j);
    Eigen::VectorXd xdot(6);
    xdot << goals[0].velocity, goals[1].velocity;
    // J qdot = xdot_d + K e: the null-space term does not disturb the task.
    EXPECT_LT((j * v.qdot - (xdot + options.feedback_gain * e)).norm(), 1e-8 * (1 + xdot.norm()));
    // With the task at rest the motion is the projected gradient step: it lowers H_jl.
    const IkVelocity rest = ik.velocity(kin, goalsAt(kin, robot.palmBody(), -1));
    Eigen::VectorXd grad;
    jointLimitCost(robot, kin.q(), &grad);
    EXPECT_LE(rest.qdot.dot(grad), 1e-12);
    EXPECT_LT((j * rest.qdot).norm(), 1e-8);
  }
}

TEST(ResolvedRateIK, PseudoInverseIsTheWeightedMinimumNorm) {
  // Without null-space gains, W qdot lies in the row space of J (the optimality condition of
  // min qdot^T W qdot subject to J qdot = xdot).
  const RobotModel& robot = test::pandaWithHand();
  IkOptions options;
  options.damping = 0.0;
  options.joint_limit_gain = 0.0;
  const ResolvedRateIK ik(robot, {{TaskKind::kPosition, robot.palmBody(), -1, -1}}, nullptr,
                          options);
  EXPECT_NEAR(ik.weights().mean(), 1.0, 1e-12);
  EXPECT_NEAR(ik.weights()[3] / ik.weights()[0], (-0.0698 + 3.0718) / (2 * 2.8973), 1e-12);
  Kinematics kin(robot);
  std::mt19937 rng(43);
  kin.update(test::randomConfiguration(robot, rng, 0.1));
  std::vector<TaskGoal> goals(1);
  goals[0].position =
      kin.relativePosition(robot.palmBody(), -1) + Eigen::Vector3d(0.02, 0.01, -0.01);
  const IkVelocity v = ik.velocity(kin, goals);
  Eigen::VectorXd e;
  Eigen::MatrixXd j;
  ik.taskError(kin, goals, e, j);
  const Eigen::VectorXd wq = ik.weights().cwiseProduct(v.qdot);
  const Eigen::VectorXd coeffs = j.transpose().colPivHouseholderQr().solve(wq);
  EXPECT_LT((j.transpose() * coeffs - wq).norm(), 1e-10 * wq.norm());
}

/// Fraction of trials in which the IK converges (1e-6 m / rad) from a start whose joints differ
/// from a solution by up to `spread` radians (spread >= range: anywhere within the limits).
double convergenceRate(double spread, unsigned seed, int trials) {
  const RobotModel& robot = test::pandaWithHand();
  const ResolvedRateIK ik(robot, palmPoseTasks(robot), nullptr, IkOptions{});
  Kinematics kin(robot);
  std::mt19937 rng(seed);
  int converged = 0;
  for (int trial = 0; trial < trials; ++trial) {
    kin.update(test::randomConfiguration(robot, rng, 0.1));
    const std::vector<TaskGoal> goals = goalsAt(kin, robot.palmBody(), -1);
    std::uniform_real_distribution<double> u(-spread, spread);
    Eigen::VectorXd q = kin.q();
    for (int i = 0; i < q.size(); ++i)
      q[i] = std::clamp(q[i] + u(rng), robot.lower()[i], robot.upper()[i]);
    kin.update(q);
    for (int it = 0; it < 1000; ++it) {
      kin.update(ik.step(kin, goals, 0.02));
      EXPECT_GE(jointLimitMargin(robot, kin.q()), 0.0);  // joints stay inside their limits
    }
    Eigen::VectorXd e;
    Eigen::MatrixXd j;
    ik.taskError(kin, goals, e, j);
    if (e.head<3>().norm() < 1e-6 && e.tail<3>().norm() < 1e-6) ++converged;
  }
  return static_cast<double>(converged) / trials;
}

TEST(ResolvedRateIK, ConvergesToReachableTargetsFromNearbyStarts) {
  EXPECT_GE(convergenceRate(0.3, 44, 40), 0.9);
}

TEST(ResolvedRateIK, ConvergesFromDistantStartsMostOfTheTime) {
  // Up to 1 rad per joint away from a solution: measured 95 % (40 trials).
  EXPECT_GE(convergenceRate(1.0, 46, 40), 0.85);
}

TEST(ResolvedRateIK, StartsAnywhereWithinTheLimitsStayWithinThem) {
  // From anywhere in the joint ranges a local method stalls where the task pulls a joint into
  // its limit (or another IK branch is needed): measured 25 % convergence (40 trials); the
  // joints never leave their limits (checked at every step inside convergenceRate).
  const double rate = convergenceRate(10.0, 46, 40);
  std::cout << "convergence from random starts: " << rate << "\n";
  EXPECT_GE(rate, 0.15);
}

TEST(ResolvedRateIK, RelativeTaskToAMovingReferenceConverges) {
  // Palm relative to link 2 (which the same joints move): eq. 1.4-1.5 with J_1 != 0.
  const RobotModel& robot = test::pandaWithHand();
  const int link2 = robot.requireBody("fer_link2");
  const ResolvedRateIK ik(robot, palmPoseTasks(robot, link2), nullptr, IkOptions{});
  Kinematics kin(robot);
  std::mt19937 rng(45);
  kin.update(test::randomConfiguration(robot, rng, 0.2));
  const std::vector<TaskGoal> goals = goalsAt(kin, robot.palmBody(), link2);
  Eigen::VectorXd q = kin.q();
  q.tail(5).array() += 0.15;
  kin.update(q);
  for (int it = 0; it < 1000; ++it) kin.update(ik.step(kin, goals, 0.02));
  Eigen::VectorXd e;
  Eigen::MatrixXd j;
  ik.taskError(kin, goals, e, j);
  EXPECT_LT(e.norm(), 1e-6);
}

TEST(ResolvedRateIK, CenterOfMassAndJointTasksConverge) {
  // Centre of mass shifted 3 cm sideways while joint 7 holds its value (eq. 1.6 + joint task).
  const RobotModel& robot = test::pandaWithHand();
  const ResolvedRateIK ik(robot,
                          {{TaskKind::kCenterOfMass, -1, -1, -1}, {TaskKind::kJoint, -1, -1, 6}},
                          nullptr, IkOptions{});
  EXPECT_EQ(ik.taskRows(), 4);
  Kinematics kin(robot);
  std::mt19937 rng(48);
  kin.update(test::randomConfiguration(robot, rng, 0.2));
  std::vector<TaskGoal> goals(2);
  goals[0].position = kin.centerOfMass() + Eigen::Vector3d(0.0, 0.03, 0.0);
  goals[1].value = kin.q()[6];
  for (int it = 0; it < 1000; ++it) kin.update(ik.step(kin, goals, 0.02));
  EXPECT_LT((kin.centerOfMass() - goals[0].position).norm(), 1e-6);
  EXPECT_NEAR(kin.q()[6], goals[1].value, 1e-6);
}

TEST(ResolvedRateIK, SingularConfigurationGivesFiniteBoundedVelocities) {
  const RobotModel& robot = test::pandaWithHand();
  const ResolvedRateIK ik(robot, palmPoseTasks(robot), nullptr, IkOptions{});
  Kinematics kin(robot);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(7);
  q[3] = -0.0698;  // arm stretched: elbow at its limit, wrist aligned
  kin.update(q);
  std::vector<TaskGoal> goals = goalsAt(kin, robot.palmBody(), -1);
  goals[0].position.z() += 0.3;  // beyond the reach
  const Eigen::VectorXd next = ik.step(kin, goals, 0.01);
  EXPECT_TRUE(next.allFinite());
  EXPECT_LE(((next - q) / 0.01).cwiseAbs().cwiseQuotient(robot.velocityLimits()).maxCoeff(),
            1.0 + 1e-12);
}

TEST(ResolvedRateIK, BadInputIsRejected) {
  const RobotModel& robot = test::pandaWithHand();
  IkOptions bad;
  bad.feedback_gain = -1;
  EXPECT_THROW(ResolvedRateIK(robot, palmPoseTasks(robot), nullptr, bad), Error);
  bad = IkOptions{};
  bad.joint_weights = Eigen::VectorXd::Ones(3);
  EXPECT_THROW(ResolvedRateIK(robot, palmPoseTasks(robot), nullptr, bad), Error);
  EXPECT_THROW(ResolvedRateIK(robot, {{TaskKind::kJoint, -1, -1, 9}}, nullptr, IkOptions{}), Error);
  const ResolvedRateIK ik(robot, palmPoseTasks(robot), nullptr, IkOptions{});
  Kinematics kin(robot);
  try {
    ik.velocity(kin, {});
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("one goal per task"), std::string::npos);
  }
}

}  // namespace
}  // namespace taskmap
