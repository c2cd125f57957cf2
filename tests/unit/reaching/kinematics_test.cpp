// Jacobians of bodies and of the relative task descriptors (eq. 1.3-1.5) against central
// finite differences of the forward kinematics.
#include "taskmap/reaching/kinematics.hpp"

#include <gtest/gtest.h>

#include "reaching_fixtures.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/pose.hpp"

namespace taskmap {
namespace {

constexpr double kStep = 1e-6;

/// Central differences of position (rows 0-2) and orientation (rows 3-5, from the rotation
/// log of R(q+h) R(q-h)^T) of `body` relative to `reference`.
Eigen::Matrix<double, 6, Eigen::Dynamic> finiteDifferenceJacobian(Kinematics& kin,
                                                                  const Eigen::VectorXd& q,
                                                                  int body, int reference) {
  Eigen::Matrix<double, 6, Eigen::Dynamic> j(6, q.size());
  for (int i = 0; i < q.size(); ++i) {
    Eigen::VectorXd qp = q, qm = q;
    qp[i] += kStep;
    qm[i] -= kStep;
    kin.update(qp);
    const Eigen::Vector3d pp = kin.relativePosition(body, reference);
    const Eigen::Matrix3d rp = kin.relativeRotation(body, reference);
    kin.update(qm);
    const Eigen::Vector3d pm = kin.relativePosition(body, reference);
    const Eigen::Matrix3d rm = kin.relativeRotation(body, reference);
    j.block<3, 1>(0, i) = (pp - pm) / (2 * kStep);
    j.block<3, 1>(3, i) = rotationLog(rp * rm.transpose()) / (2 * kStep);
  }
  kin.update(q);
  return j;
}

double relativeError(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / std::max(1.0, b.norm());
}

void expectJacobiansMatch(const RobotModel& robot, int samples, unsigned seed) {
  std::mt19937 rng(seed);
  Kinematics kin(robot);
  const int n = static_cast<int>(robot.bodies().size());
  for (int s = 0; s < samples; ++s) {
    const Eigen::VectorXd q = test::randomConfiguration(robot, rng);
    kin.update(q);
    for (int body = 0; body < n; ++body) {
      const int reference = (body * 7 + s) % (n + 1) - 1;  // world and moving bodies
      Eigen::Matrix<double, 6, Eigen::Dynamic> analytic(6, robot.dofs());
      analytic.topRows<3>() = kin.relativePositionJacobian(body, reference);
      analytic.bottomRows<3>() = kin.relativeAngularJacobian(body, reference);
      const auto fd = finiteDifferenceJacobian(kin, q, body, reference);
      EXPECT_LT(relativeError(analytic, fd), 1e-6)
          << robot.bodies()[body].name << " relative to " << reference << "\nanalytic\n"
          << analytic << "\nfd\n"
          << fd;
      if (reference < 0) {
        EXPECT_LT(relativeError(kin.jacobian(body), fd), 1e-6);
      }
    }
  }
}

TEST(Kinematics, PandaWithHandJacobiansMatchFiniteDifferences) {
  expectJacobiansMatch(test::pandaWithHand(), 5, 1);
}

TEST(Kinematics, MixedJointKindsMatchFiniteDifferences) {
  const RobotModel robot =
      RobotModel::load(test::writeTempFile("mixed.urdf", test::mixedJointsUrdf()));
  ASSERT_EQ(robot.dofs(), 4);
  expectJacobiansMatch(robot, 10, 2);
}

TEST(Kinematics, PointJacobianMatchesFiniteDifferencesOfABodyFixedPoint) {
  const RobotModel& robot = test::pandaWithHand();
  Kinematics kin(robot);
  std::mt19937 rng(3);
  const Eigen::VectorXd q = test::randomConfiguration(robot, rng);
  kin.update(q);
  const int body = robot.requireBody("fer_link5");
  const Eigen::Vector3d local(0.03, -0.02, 0.1);
  const Eigen::Matrix3Xd j = kin.pointJacobian(body, kin.pose(body) * local);
  Eigen::Matrix3Xd fd(3, robot.dofs());
  for (int i = 0; i < robot.dofs(); ++i) {
    Eigen::VectorXd qp = q, qm = q;
    qp[i] += kStep;
    qm[i] -= kStep;
    kin.update(qp);
    const Eigen::Vector3d a = kin.pose(body) * local;
    kin.update(qm);
    fd.col(i) = (a - kin.pose(body) * local) / (2 * kStep);
  }
  EXPECT_LT(relativeError(j, fd), 1e-6);
  // Joints beyond link5 do not move it.
  EXPECT_EQ(j.rightCols(2).norm(), 0.0);
}

/// addJacobianAdjoint against central differences of sum_ij G_ij J_ij(q), random G, every body.
void expectJacobianAdjointMatches(const RobotModel& robot, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Kinematics kin(robot);
  const Eigen::VectorXd q = test::randomConfiguration(robot, rng);
  for (int body = 0; body < static_cast<int>(robot.bodies().size()); ++body) {
    Eigen::Matrix<double, 6, Eigen::Dynamic> g(6, robot.dofs());
    for (int i = 0; i < g.size(); ++i) g.data()[i] = normal(rng);
    kin.update(q);
    Eigen::VectorXd analytic = Eigen::VectorXd::Zero(robot.dofs());
    kin.addJacobianAdjoint(body, g, analytic);
    Eigen::VectorXd fd(robot.dofs());
    for (int k = 0; k < robot.dofs(); ++k) {
      Eigen::VectorXd qp = q, qm = q;
      qp[k] += kStep;
      qm[k] -= kStep;
      kin.update(qp);
      const double plus = g.cwiseProduct(kin.jacobian(body)).sum();
      kin.update(qm);
      fd[k] = (plus - g.cwiseProduct(kin.jacobian(body)).sum()) / (2 * kStep);
    }
    EXPECT_LT(relativeError(analytic, fd), 1e-7)
        << robot.bodies()[body].name << "\nanalytic " << analytic.transpose() << "\nfd "
        << fd.transpose();
  }
}

TEST(Kinematics, JacobianAdjointMatchesFiniteDifferences) {
  expectJacobianAdjointMatches(test::pandaWithHand(), 4);
  expectJacobianAdjointMatches(
      RobotModel::load(test::writeTempFile("mixed.urdf", test::mixedJointsUrdf())), 5);
}

TEST(Kinematics, CenterOfMassAndItsJacobian) {
  const RobotModel& robot = test::pandaWithHand();
  double total = 0.0;
  for (const RobotBody& b : robot.bodies()) total += b.mass;
  EXPECT_NEAR(total, 16.18253, 1e-9);  // sum of the Panda's link masses (inertials.yaml)
  Kinematics kin(robot);
  std::mt19937 rng(4);
  for (int s = 0; s < 5; ++s) {
    const Eigen::VectorXd q = test::randomConfiguration(robot, rng);
    kin.update(q);
    const Eigen::Matrix3Xd j = kin.centerOfMassJacobian();
    Eigen::Matrix3Xd fd(3, q.size());
    for (int i = 0; i < q.size(); ++i) {
      Eigen::VectorXd qp = q, qm = q;
      qp[i] += kStep;
      qm[i] -= kStep;
      kin.update(qp);
      const Eigen::Vector3d a = kin.centerOfMass();
      kin.update(qm);
      fd.col(i) = (a - kin.centerOfMass()) / (2 * kStep);
    }
    EXPECT_LT(relativeError(j, fd), 1e-6);
    EXPECT_EQ(j.col(0).z(), 0.0);  // the first joint turns about the vertical
  }
  const RobotModel mixed =
      RobotModel::load(test::writeTempFile("mixed_com.urdf", test::mixedJointsUrdf()));
  EXPECT_THROW(Kinematics(mixed).centerOfMass(), Error);  // no <inertial>: no mass
}

TEST(Kinematics, RejectsWrongConfigurations) {
  Kinematics kin(test::pandaWithHand());
  try {
    kin.update(Eigen::VectorXd::Zero(3));
    FAIL() << "expected Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("has 3 values"), std::string::npos) << e.what();
  }
  Eigen::VectorXd q = Eigen::VectorXd::Zero(7);
  q[2] = std::nan("");
  EXPECT_THROW(kin.update(q), Error);
}

}  // namespace
}  // namespace taskmap
