// Forward kinematics and Jacobians against KDL (orocos-kdl, an independent implementation).
// The KDL chains are built from the Panda's published joint origins (kinematics.yaml of
// franka_description, written out here), not from our URDF reader.
#include <gtest/gtest.h>

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include "reaching_fixtures.hpp"
#include "taskmap/reaching/kinematics.hpp"

namespace taskmap {
namespace {

struct Origin {
  double x, y, z, roll, pitch, yaw;
};

// Joint origins of joints 1..7 and the flange (joint8) of the Panda.
const Origin kPanda[8] = {{0, 0, 0.333, 0, 0, 0},
                          {0, 0, 0, -M_PI / 2, 0, 0},
                          {0, -0.316, 0, M_PI / 2, 0, 0},
                          {0.0825, 0, 0, M_PI / 2, 0, 0},
                          {-0.0825, 0.384, 0, -M_PI / 2, 0, 0},
                          {0, 0, 0, M_PI / 2, 0, 0},
                          {0.088, 0, 0, M_PI / 2, 0, 0},
                          {0, 0, 0.107, 0, 0, 0}};

KDL::Frame frameOf(const Origin& o) {
  return KDL::Frame(KDL::Rotation::RPY(o.roll, o.pitch, o.yaw), KDL::Vector(o.x, o.y, o.z));
}

KDL::Frame frameOf(const Eigen::Isometry3d& t) {
  KDL::Frame f;
  for (int r = 0; r < 3; ++r) {
    f.p(r) = t.translation()[r];
    for (int c = 0; c < 3; ++c) f.M(r, c) = t.linear()(r, c);
  }
  return f;
}

/// Panda chain to link `links` (1..7) or, for 8, to the flange, optionally followed by the palm
/// adapter.
KDL::Chain pandaChain(const Eigen::Isometry3d* palm_in_flange, int links = 8) {
  KDL::Chain chain;
  for (int i = 0; i < std::min(links, 7); ++i) {
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), frameOf(kPanda[i])));
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ), KDL::Frame::Identity()));
  }
  if (links < 8) return chain;
  chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), frameOf(kPanda[7])));
  if (palm_in_flange)
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), frameOf(*palm_in_flange)));
  return chain;
}

void expectMatchesKdl(const RobotModel& robot, const KDL::Chain& chain, int body, unsigned seed) {
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jac(chain);
  Kinematics kin(robot);
  std::mt19937 rng(seed);
  const int n = static_cast<int>(chain.getNrOfJoints());
  for (int s = 0; s < 50; ++s) {
    const Eigen::VectorXd q = test::randomConfiguration(robot, rng, 0.0);
    KDL::JntArray kq(static_cast<unsigned>(n));
    kq.data = q.head(n);
    KDL::Frame f;
    KDL::Jacobian kj(kq.rows());
    ASSERT_GE(fk.JntToCart(kq, f), 0);
    ASSERT_GE(jac.JntToJac(kq, kj), 0);
    kin.update(q);
    const Eigen::Isometry3d& t = kin.pose(body);
    for (int r = 0; r < 3; ++r) {
      EXPECT_NEAR(t.translation()[r], f.p(r), 1e-12);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(t.linear()(r, c), f.M(r, c), 1e-12);
    }
    EXPECT_LT((kin.jacobian(body) - kj.data).norm(), 1e-12) << "ours\n"
                                                            << kin.jacobian(body) << "\nKDL\n"
                                                            << kj.data;
  }
}

TEST(KdlOracle, EveryPandaLinkMatchesKdl) {
  const RobotModel& robot = test::pandaWithHand();
  for (int link = 1; link <= 7; ++link)
    expectMatchesKdl(robot, pandaChain(nullptr, link),
                     robot.requireBody("fer_link" + std::to_string(link)), 20 + link);
}

TEST(KdlOracle, PandaFlangeMatchesKdl) {
  const RobotModel& robot = test::pandaWithHand();
  expectMatchesKdl(robot, pandaChain(nullptr), robot.requireBody("fer_link8"), 11);
}

TEST(KdlOracle, PalmThroughTheAdapterMatchesKdl) {
  const RobotModel& robot = test::pandaWithHand();
  const Eigen::Isometry3d adapter = RobotModel::humanoidMountOnPanda().palm_in_flange;
  expectMatchesKdl(robot, pandaChain(&adapter), robot.palmBody(), 12);
}

TEST(KdlOracle, PrismaticAndTiltedAxesMatchKdl) {
  // Path base -> a -> b -> c of the mixed-joint URDF, written as KDL joints with their axes.
  const RobotModel robot =
      RobotModel::load(test::writeTempFile("mixed_kdl.urdf", test::mixedJointsUrdf()));
  KDL::Chain chain;
  const auto seg = [&](const Origin& o, KDL::Vector axis, KDL::Joint::JointType type) {
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), frameOf(o)));
    axis.Normalize();
    chain.addSegment(
        KDL::Segment(KDL::Joint(KDL::Vector::Zero(), axis, type), KDL::Frame::Identity()));
  };
  seg({0.1, 0.0, 0.2, 0.3, -0.2, 0.5}, KDL::Vector(0.2, 0.3, 1), KDL::Joint::RotAxis);
  seg({0, 0.05, 0.2, 0.1, 0.7, 0}, KDL::Vector(1, 0, 1), KDL::Joint::TransAxis);
  seg({0.02, 0, 0.25, 0, 0, 0.4}, KDL::Vector(0, 1, 0), KDL::Joint::RotAxis);
  // Dof order j1, j2, j3, j4; the chain ends at c, so j4 (branch d) stays out of it.
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jac(chain);
  Kinematics kin(robot);
  std::mt19937 rng(13);
  const int c = robot.requireBody("c");
  for (int s = 0; s < 50; ++s) {
    const Eigen::VectorXd q = test::randomConfiguration(robot, rng, 0.0);
    KDL::JntArray kq(3);
    kq.data = q.head(3);
    KDL::Frame f;
    KDL::Jacobian kj(3);
    ASSERT_GE(fk.JntToCart(kq, f), 0);
    ASSERT_GE(jac.JntToJac(kq, kj), 0);
    kin.update(q);
    for (int r = 0; r < 3; ++r) EXPECT_NEAR(kin.pose(c).translation()[r], f.p(r), 1e-12);
    const Eigen::MatrixXd ours = kin.jacobian(c);
    EXPECT_LT((ours.leftCols(3) - kj.data).norm(), 1e-12);
    EXPECT_EQ(ours.col(3).norm(), 0.0);
  }
}

}  // namespace
}  // namespace taskmap
