// The map terms over a movement (Fig. 1.16): at every step they equal the terminal cost's terms
// (mapTerminalCost, one TaskMap::evaluate per call) at that configuration; the palm pose in the
// object frame against the inverse of the world poses; wrong sizes refused.
#include "taskmap/reaching/movement_terms.hpp"

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "reaching_fixtures.hpp"
#include "synthetic_map.hpp"
#include "taskmap/reaching/reach_scene.hpp"

namespace taskmap {
namespace {

TEST(MovementTerms, EveryStepEqualsTheTerminalCostThere) {
  RobotModel robot = test::pandaWithHand();
  addSceneTo(defaultReachScene(), robot);
  const int palm = robot.palmBody(), object = robot.requireBody("object");
  TaskMapOptions o;
  o.position_sigma = 0.3;  // wide kernels: the quality term is non-zero along the movement
  const TaskMap map = TaskMap::fromData(testing::syntheticMap(200), o);
  Eigen::VectorXd ready(7);
  ready << 0.0, -M_PI / 4, 0.0, -3 * M_PI / 4, 0.0, M_PI / 2, M_PI / 4;
  std::vector<Eigen::VectorXd> q;
  for (int t = 0; t <= 20; ++t) q.push_back(ready + 0.02 * t * Eigen::VectorXd::Ones(7));
  MapCostWeights w;
  w.proximity = 2.0;
  w.quality = 3.0;
  const MovementTerms m = movementTerms(map, robot, palm, object, q, w);
  ASSERT_EQ(m.proximity.size(), q.size());
  ASSERT_EQ(m.quality.size(), q.size());
  auto record = std::make_shared<MapCostRecord>();
  const TerminalCost cost = mapTerminalCost(map, palm, object, w, {}, record);
  Kinematics kin(robot);
  int quality_terms = 0;
  for (std::size_t t = 0; t < q.size(); ++t) {
    kin.update(q[t]);
    cost(kin, nullptr);
    EXPECT_NEAR(m.proximity[t], record->proximity, 1e-12 * (1 + record->proximity)) << t;
    EXPECT_NEAR(m.quality[t], record->quality, 1e-12 * (1 + std::abs(record->quality))) << t;
    quality_terms += record->quality < 0.0;
    const Pose rel = poseInFrameOf(kin, palm, object);
    const Eigen::Isometry3d expected = kin.pose(object).inverse() * kin.pose(palm);
    EXPECT_LT((rel.toIsometry().matrix() - expected.matrix()).norm(), 1e-12);
  }
  EXPECT_GT(quality_terms, 0);  // the quality term is exercised
}

TEST(MovementTerms, RefusesConfigurationsOfTheWrongSize) {
  RobotModel robot = test::pandaWithHand();
  addSceneTo(defaultReachScene(), robot);
  const TaskMap map = TaskMap::fromData(testing::syntheticMap(20));
  EXPECT_TRUE(testing::throwsError(
      [&] {
        movementTerms(map, robot, robot.palmBody(), robot.requireBody("object"),
                      {Eigen::VectorXd::Zero(3)}, {});
      },
      {"configuration 0", "3 values"}));
}

}  // namespace
}  // namespace taskmap
