// The task map as terminal cost (eq. 1.22): the joint-space gradient of w_p g_p + w_q g_q at the
// final hand pose against central differences over the joints, and the whole trajectory
// gradient with the map term against differences of complete rollouts (nearest sample fixed).
#include "taskmap/reaching/map_cost.hpp"

#include <gtest/gtest.h>

#include <iostream>

#include "reaching_fixtures.hpp"
#include "synthetic_map.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/reaching/reach_scene.hpp"

namespace taskmap {
namespace {

const TaskMap& map() {
  TaskMapOptions o;
  o.quality_mode = QualityMode::kExact;
  o.position_sigma = 0.3;  // wide kernels: the quality term is non-zero at the arm's start
  static const TaskMap m = TaskMap::fromData(testing::syntheticMap(300), o);
  return m;
}

struct Scene {
  RobotModel robot = test::pandaInDefaultScene();
  int object = robot.requireBody("object");
};

TEST(MapCost, JointGradientMatchesCentralDifferences) {
  const Scene s;
  auto record = std::make_shared<MapCostRecord>();
  MapCostWeights w;
  w.quality = 5.0;
  const TerminalCost cost = mapTerminalCost(map(), s.robot.palmBody(), s.object, w, {}, record);
  Kinematics kin(s.robot);
  Eigen::VectorXd q = test::readyPose();
  q[0] += 0.2;
  kin.update(q);
  Eigen::VectorXd g;
  const double c = cost(kin, &g);
  const std::int64_t nearest =
      static_cast<std::int64_t>(record->evaluation.proximity.nearest.index);
  EXPECT_NEAR(c, record->proximity + record->quality, 1e-12);
  EXPECT_LT(record->quality, 0.0);  // the quality chain is exercised
  Eigen::VectorXd fd(q.size());
  for (int i = 0; i < q.size(); ++i) {
    Eigen::VectorXd plus = q, minus = q;
    plus[i] += 1e-6;
    minus[i] -= 1e-6;
    kin.update(plus);
    const double cp = cost(kin, nullptr);
    EXPECT_EQ(static_cast<std::int64_t>(record->evaluation.proximity.nearest.index), nearest);
    kin.update(minus);
    fd[i] = (cp - cost(kin, nullptr)) / 2e-6;
  }
  const double rel = (g - fd).norm() / fd.norm();
  std::cout << "map cost " << c << ", relative gradient error " << rel << "\n";
  EXPECT_LT(rel, 1e-6);
  EXPECT_EQ(record->calls, 1 + 2 * q.size());
}

TEST(MapCost, TrajectoryGradientWithTheMapMatchesCentralDifferences) {
  const Scene s;
  CollisionOptions co;
  co.hand_may_touch = {"object"};
  const CollisionModel collisions(s.robot, co);
  TrajectoryProblem p;
  p.robot = &s.robot;
  p.collisions = &collisions;
  p.body = s.robot.palmBody();
  p.reference = s.object;
  p.q0 = test::readyPose();
  p.reach.steps = 50;
  p.reach.move_time = 0.4;
  auto record = std::make_shared<MapCostRecord>();
  p.terminal = mapTerminalCost(map(), p.body, p.reference, MapCostWeights{}, 2, record);
  Eigen::Matrix<double, 6, 1> point = startTaskVariables(p);
  point.head<3>() += Eigen::Vector3d(0.05, -0.03, -0.04);
  const std::vector<Eigen::VectorXd> points{point};
  const TrajectoryCost c = evaluateTrajectory(p, points, true);
  const std::size_t nearest = record->evaluation.proximity.nearest.index;
  Eigen::VectorXd fd(6);
  for (int i = 0; i < 6; ++i) {
    std::vector<Eigen::VectorXd> plus = points, minus = points;
    plus[0][i] += 1e-5;
    minus[0][i] -= 1e-5;
    const double cp = evaluateTrajectory(p, plus, false).total;
    EXPECT_EQ(record->evaluation.proximity.nearest.index, nearest);
    fd[i] = (cp - evaluateTrajectory(p, minus, false).total) / 2e-5;
  }
  const double rel = (c.gradient - fd).norm() / fd.norm();
  std::cout << "terminal " << c.terminal << ", relative gradient error " << rel << "\n";
  EXPECT_GT(c.terminal, 0.0);
  EXPECT_LT(rel, 1e-5);
}

TEST(MapCost, RefusesAnUnknownClusterAndNegativeWeights) {
  const Scene s;
  EXPECT_THROW(mapTerminalCost(map(), s.robot.palmBody(), s.object, {}, 7, nullptr), Error);
  MapCostWeights w;
  w.quality = -1.0;
  try {
    mapTerminalCost(map(), s.robot.palmBody(), s.object, w, {}, nullptr);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("quality"), std::string::npos);
  }
}

// q* is the best quality at the map's own grasps, and the quality term is w_q g_q / q* with its
// gradient scaled alike (docs/REACHING.md "The quality term's scale").
TEST(MapCost, TheQualityTermIsRelativeToTheMapsBestGrasp) {
  const TaskMap& m = map();
  const double peak = mapQualityPeak(m);
  const BatchEvaluation at = m.evaluateBatch(m.data().grasps.pose);
  EXPECT_DOUBLE_EQ(peak, -at.quality.minCoeff());
  EXPECT_GT(peak, 0.0);
  const Scene s;
  Kinematics kin(s.robot);
  Eigen::VectorXd q = test::readyPose();
  q[0] += 0.2;
  kin.update(q);
  auto raw = std::make_shared<MapCostRecord>(), scaled = std::make_shared<MapCostRecord>();
  MapCostWeights w;
  w.quality = 5.0;
  Eigen::VectorXd g_raw, g_scaled;
  mapTerminalCost(m, s.robot.palmBody(), s.object, w, {}, raw)(kin, &g_raw);
  w.quality_peak = peak;
  w.proximity = 0.0;
  mapTerminalCost(m, s.robot.palmBody(), s.object, w, {}, scaled)(kin, &g_scaled);
  EXPECT_NEAR(scaled->quality, raw->quality / peak, 1e-12 * std::abs(raw->quality));
  EXPECT_GE(scaled->quality, -5.0 * 2.0);  // of the order of w_q at most
  w.proximity = 1.0;
  w.quality = 0.0;
  Eigen::VectorXd g_prox;
  mapTerminalCost(m, s.robot.palmBody(), s.object, w, {}, nullptr)(kin, &g_prox);
  EXPECT_LT((g_scaled - (g_raw - g_prox) / peak).norm(), 1e-9 * g_raw.norm());
  w.quality_peak = 0.0;
  EXPECT_THROW(mapTerminalCost(m, s.robot.palmBody(), s.object, w, {}, nullptr), Error);
}

}  // namespace
}  // namespace taskmap
