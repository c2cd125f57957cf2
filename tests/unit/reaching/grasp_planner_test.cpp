// Grasp planner screening (docs/REACHING.md "Screening"): with every reachable cluster screened by
// a short optimisation, the winner is re-run in full and its plan equals the one the unscreened
// run makes from that cluster; the others keep their short runs. Invalid options are refused.
#include "taskmap/reaching/grasp_planner.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <iostream>
#include <utility>
#include <vector>

#include "reaching_fixtures.hpp"
#include "synthetic_map.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/reaching/kinematics.hpp"

namespace taskmap {
namespace {

/// The Panda with the humanoid hand in the paper's basket scene (reference position), its
/// collision model (the hand may touch the basket) and a 300-step reach from the ready pose.
struct BasketScene {
  BasketScene() : robot(withScene()), collisions(robot, handMayTouch()) {}
  static ReachScene scene() {
    return loadReachScene(std::string(TASKMAP_SOURCE_DIR) +
                          "/reaching/scenes/basket_reference.json");
  }
  static RobotModel withScene() {
    RobotModel r = test::pandaWithHand();
    addSceneTo(scene(), r);
    return r;
  }
  static CollisionOptions handMayTouch() {
    CollisionOptions co;
    co.hand_may_touch = {scene().object};
    return co;
  }
  TrajectoryProblem problem() const {
    TrajectoryProblem p;
    p.robot = &robot;
    p.collisions = &collisions;
    p.body = robot.palmBody();
    p.reference = robot.requireBody(scene().object);
    p.q0 = test::readyPose();
    p.reach.steps = 300;
    return p;
  }
  RobotModel robot;
  CollisionModel collisions;
};

TEST(GraspPlanner, ScreeningRerunsTheCheapestClusterInFull) {
  const BasketScene basket;
  TaskMapOptions mo;
  mo.quality_mode = QualityMode::kExact;
  // The synthetic basket map (one cluster per bar; the Panda reaches bar 2 only here) with bar 2
  // split into two clusters by grasp parity: two reachable clusters to screen.
  TaskMapData data = testing::syntheticMap(300);
  ClusteringResult& c = *data.clustering;
  c.clusters.push_back(ClusterSummary{});
  c.clusters[2] = ClusterSummary{};
  for (std::size_t i = 0; i < c.labels.size(); ++i) {
    if (c.labels[i] != 2) continue;
    if (i % 2 == 1) c.labels[i] = 3;
    ClusterSummary& summary = c.clusters[static_cast<std::size_t>(c.labels[i])];
    ++summary.size;
    if (summary.representative < 0 || data.grasps.epsilon[i] > summary.best_epsilon) {
      summary.representative = static_cast<int>(i);
      summary.best_epsilon = data.grasps.epsilon[i];
    }
  }
  const TaskMap map = TaskMap::fromData(data, mo);
  const TrajectoryProblem p = basket.problem();
  GraspPlanOptions o;
  o.all_clusters = true;
  o.optimizer.max_iterations = 6;
  o.screen_iterations = 0;
  const GraspPlan full = planGrasp(p, map, o);
  ASSERT_GE(full.plans.size(), 2u) << full.message;  // screening has something to choose
  o.screen_iterations = 2;
  const GraspPlan screened = planGrasp(p, map, o);
  ASSERT_EQ(screened.plans.size(), full.plans.size());
  ASSERT_GE(screened.best, 0);
  // Every plan re-run in full (the cheapest, and the next one when the full run of the first
  // became unsafe) equals the unscreened run's from its cluster; the best is one of them and is
  // the unscreened run's best.
  int full_runs = 0;
  for (std::size_t i = 0; i < screened.plans.size(); ++i) {
    const int iterations = screened.plans[i].optimization.iterations;
    std::cout << "cluster " << screened.plans[i].cluster << ": " << iterations
              << " iterations, cost " << screened.plans[i].optimization.cost.total
              << " (unscreened " << full.plans[i].optimization.cost.total << ")"
              << (screened.plans[i].sample_out_of_reach ? ", sample out of reach" : "") << "\n";
    if (iterations > 2) {
      EXPECT_EQ(iterations, full.plans[i].optimization.iterations);
      EXPECT_EQ(screened.plans[i].optimization.cost.total, full.plans[i].optimization.cost.total);
      EXPECT_EQ(screened.plans[i].grasp_index, full.plans[i].grasp_index);
      ++full_runs;
    }
  }
  EXPECT_GE(full_runs, 1);
  EXPECT_GT(screened.plans[static_cast<std::size_t>(screened.best)].optimization.iterations, 2);
  EXPECT_EQ(screened.best, full.best);
  o.screen_iterations = -1;
  try {
    planGrasp(p, map, o);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("screen_iterations"), std::string::npos);
  }
}

// The run control (core/run_control.hpp): a caller's on_iteration is chained after the
// planner's bookkeeping (it used to be replaced silently), progress comes once per iteration,
// and a raised stop flag ends the plan as kInterrupted.
TEST(GraspPlanner, ChainsTheCallersCallbackAndStopsOnTheFlag) {
  const BasketScene basket;
  const TaskMap map = TaskMap::fromData(testing::syntheticMap(300), {});
  const TrajectoryProblem p = basket.problem();
  GraspPlanOptions o;
  o.optimizer.max_iterations = 3;
  int caller_calls = 0;
  o.optimizer.on_iteration = [&caller_calls](int, const TrajectoryCost&) { ++caller_calls; };
  RunControl<PlanProgress> control;
  std::vector<PlanProgress> reports;
  control.progress = [&reports](const PlanProgress& r) { reports.push_back(r); };
  const GraspPlan plan = planGrasp(p, map, o, control);
  ASSERT_EQ(plan.plans.size(), 1u) << plan.message;
  const ClusterPlan& c = plan.plans[0];
  EXPECT_EQ(caller_calls, c.optimization.iterations + 1);  // the start, then every iteration
  EXPECT_EQ(c.proximity.size(), static_cast<std::size_t>(caller_calls));  // bookkeeping kept
  ASSERT_EQ(reports.size(), static_cast<std::size_t>(caller_calls));
  EXPECT_EQ(reports.back().cluster, c.cluster);
  EXPECT_EQ(reports.back().iteration, c.optimization.iterations);
  EXPECT_EQ(reports.back().cost, c.optimization.cost.total);
  const std::atomic<bool> stop{true};
  control.stop = &stop;
  const GraspPlan stopped = planGrasp(p, map, o, control);
  EXPECT_EQ(stopped.status, GraspPlanStatus::kInterrupted);
  EXPECT_TRUE(stopped.plans.empty());
  EXPECT_EQ(stopped.best, -1);
}

// When every plan is unsafe (docs/REACHING.md "When every plan is unsafe"): a second round
// plans from other members of the clusters and from the outliers; its plans follow the first
// round's, each after its rank, and the best is the cheapest of all (safe first). With a kernel
// of 10 micrometres and the optimiser's own last step (not bent onto the sample) no plan ends
// on the manifold, so every plan here is unsafe. Without member tries there is no second round.
TEST(GraspPlanner, OtherMembersArePlannedWhenEveryPlanIsUnsafe) {
  const BasketScene basket;
  TaskMapOptions mo;
  mo.position_sigma = 1e-5;
  const TaskMap map = TaskMap::fromData(testing::syntheticMap(300), mo);
  const TrajectoryProblem p = basket.problem();
  GraspPlanOptions o;
  o.optimizer.max_iterations = 2;
  o.end_on_sample = false;
  o.ranking.member_tries = 0;
  const GraspPlan one = planGrasp(p, map, o);
  ASSERT_EQ(one.plans.size(), 1u) << one.message;
  EXPECT_EQ(one.status, GraspPlanStatus::kUnsafe) << one.message;
  EXPECT_LT(one.plans[0].iterations_to_manifold, 0);
  o.ranking.member_tries = 4;
  const GraspPlan more = planGrasp(p, map, o);
  EXPECT_EQ(more.status, GraspPlanStatus::kUnsafe) << more.message;
  ASSERT_GT(more.plans.size(), 1u) << more.message;
  EXPECT_EQ(more.plans[0].optimization.cost.total, one.plans[0].optimization.cost.total);
  ASSERT_GE(more.ranking.size(), more.plans.size());
  const auto& clustering = *map.data().clustering;
  for (std::size_t i = 0; i < more.plans.size(); ++i) {
    const ClusterRank& r = more.ranking[i];
    EXPECT_TRUE(r.reachable) << i;
    EXPECT_EQ(more.plans[i].cluster, r.cluster) << i;
    if (i > 0 && r.cluster >= 0) {  // the second round skips the representatives
      EXPECT_NE(static_cast<int>(r.target),
                clustering.clusters[static_cast<std::size_t>(r.cluster)].representative)
          << i;
    }
    EXPECT_GE(more.plans[i].optimization.cost.total,
              more.plans[static_cast<std::size_t>(more.best)].optimization.cost.total)
        << i;
  }
}

// Ending on the sample (docs/REACHING.md "Ending on the sample"): with end_on_sample the last
// step's palm pose relative to the object is the final nearest sample's (to the IK's 1e-7 m and
// 1e-6 rad); only the last end_steps steps differ from the optimiser's trajectory, the bend
// stays within the joint limits, and the optimiser's costs and measures are kept. Without it
// the last step is the optimiser's, off the sample.
TEST(GraspPlanner, EndsOnItsSampleWithinTheLimits) {
  const BasketScene basket;
  const RobotModel& robot = basket.robot;
  const TaskMap map = TaskMap::fromData(testing::syntheticMap(300), {});
  const TrajectoryProblem p = basket.problem();
  GraspPlanOptions o;
  o.optimizer.max_iterations = 4;
  o.end_on_sample = false;
  const GraspPlan free_end = planGrasp(p, map, o);
  o.end_on_sample = true;
  const GraspPlan on_sample = planGrasp(p, map, o);
  ASSERT_EQ(free_end.plans.size(), 1u) << free_end.message;
  ASSERT_EQ(on_sample.plans.size(), 1u) << on_sample.message;
  const ClusterPlan &a = free_end.plans[0], &b = on_sample.plans[0];
  EXPECT_FALSE(a.ends_on_sample);
  ASSERT_TRUE(b.ends_on_sample);
  EXPECT_FALSE(b.sample_out_of_reach);
  EXPECT_EQ(a.grasp_index, b.grasp_index);
  EXPECT_EQ(a.optimization.cost.total, b.optimization.cost.total);
  EXPECT_EQ(a.iterations_to_manifold, b.iterations_to_manifold);
  const std::vector<Eigen::VectorXd>&qa = a.optimization.cost.q, &qb = b.optimization.cost.q;
  ASSERT_EQ(qa.size(), qb.size());
  for (std::size_t t = 0; t + 50 < qa.size(); ++t) EXPECT_EQ(qa[t], qb[t]) << t;
  const Pose sample = map.data().grasps.poseAt(static_cast<std::size_t>(b.grasp_index));
  const auto offSample = [&](const Eigen::VectorXd& q) {
    Kinematics kin(robot);
    kin.update(q);
    const Eigen::Vector3d dp = kin.relativePosition(p.body, p.reference) - sample.position;
    const Eigen::Quaterniond r(kin.relativeRotation(p.body, p.reference));
    return std::make_pair(dp.norm(), r.angularDistance(sample.orientation));
  };
  const auto [pa, ra] = offSample(qa.back());
  const auto [pb, rb] = offSample(qb.back());
  std::cout << "last step off the sample: optimiser " << 1e3 * pa << " mm, " << ra << " rad; bent "
            << pb << " m, " << rb << " rad\n";
  EXPECT_LT(pb, 1e-6);
  EXPECT_LT(rb, 1e-5);
  EXPECT_GT(pa, 10 * pb);
  for (const Eigen::VectorXd& q : qb) {
    EXPECT_TRUE((q.array() >= robot.lower().array()).all());
    EXPECT_TRUE((q.array() <= robot.upper().array()).all());
  }
  o.end_steps = 0;
  EXPECT_THROW(planGrasp(p, map, o), Error);
}

}  // namespace
}  // namespace taskmap
