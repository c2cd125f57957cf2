// Cost of one trajectory optimisation iteration (section 1.5) on the Panda with the humanoid
// hand in the default scene, 300 steps, two attractor points: the forward rollout with the cost
// terms (the baseline, one line-search trial) and the rollout with the backward pass (the
// gradient). Per plan: `taskmap reach --map ... --json` reports ms_per_plan (docs/REACHING.md).
#include <benchmark/benchmark.h>

#include <memory>

#include "taskmap/reaching/reach_scene.hpp"
#include "taskmap/reaching/trajectory_optimizer.hpp"

namespace taskmap {
namespace {

struct Setup {
  RobotModel robot;
  std::unique_ptr<CollisionModel> collisions;
  TrajectoryProblem problem;
  std::vector<Eigen::VectorXd> points;
};

const Setup& setup() {
  static Setup s = [] {
    Setup out;
    out.robot = RobotModel::pandaWithHumanoidHand(
        std::string(TASKMAP_SOURCE_DIR) + "/reaching/robots", TASKMAP_HANDS_DIR);
    const ReachScene scene = defaultReachScene();
    addSceneTo(scene, out.robot);
    CollisionOptions co;
    co.hand_may_touch = {scene.object};
    out.collisions = std::make_unique<CollisionModel>(out.robot, co);
    TrajectoryProblem& p = out.problem;
    p.robot = &out.robot;
    p.collisions = out.collisions.get();
    p.body = out.robot.palmBody();
    p.reference = out.robot.requireBody(scene.object);
    p.q0.resize(7);
    p.q0 << 0.0, -M_PI / 4, 0.0, -3 * M_PI / 4, 0.0, M_PI / 2, M_PI / 4;
    p.frame = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).matrix();
    const Eigen::Matrix<double, 6, 1> x0 = startTaskVariables(p);
    Eigen::Matrix<double, 6, 1> target = Eigen::Matrix<double, 6, 1>::Zero();
    target.head<3>() = Eigen::Vector3d(-0.07, 0.0, 0.02);
    out.points = {0.5 * (x0 + target), target};
    return out;
  }();
  return s;
}

void BM_RolloutAndCost(benchmark::State& state) {
  const Setup& s = setup();
  for (auto _ : state) benchmark::DoNotOptimize(evaluateTrajectory(s.problem, s.points, false));
  state.counters["steps"] = s.problem.reach.steps;
}
BENCHMARK(BM_RolloutAndCost)->Unit(benchmark::kMillisecond);

void BM_RolloutCostAndGradient(benchmark::State& state) {
  const Setup& s = setup();
  for (auto _ : state) benchmark::DoNotOptimize(evaluateTrajectory(s.problem, s.points, true));
  state.counters["steps"] = s.problem.reach.steps;
}
BENCHMARK(BM_RolloutCostAndGradient)->Unit(benchmark::kMillisecond);

void BM_RolloutCostAndForwardDifferenceGradient(benchmark::State& state) {
  const Setup& s = setup();
  TrajectoryProblem p = s.problem;
  p.step_derivative = StepDerivative::kFiniteDifferences;
  p.central_step_jacobian = false;
  p.step_jacobian_epsilon = 1e-8;
  for (auto _ : state) benchmark::DoNotOptimize(evaluateTrajectory(p, s.points, true));
  state.counters["steps"] = p.reach.steps;
}
BENCHMARK(BM_RolloutCostAndForwardDifferenceGradient)->Unit(benchmark::kMillisecond);

void BM_TenIterations(benchmark::State& state) {
  const Setup& s = setup();
  TrajectoryOptimizerOptions o;
  o.max_iterations = 10;
  o.relative_tolerance = 0.0;
  for (auto _ : state) benchmark::DoNotOptimize(optimizeTrajectory(s.problem, s.points, o));
}
BENCHMARK(BM_TenIterations)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace taskmap

BENCHMARK_MAIN();
