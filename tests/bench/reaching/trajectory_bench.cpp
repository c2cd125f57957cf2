// Cost of one trajectory optimisation iteration (section 1.5) on the Panda with the humanoid
// hand in the default scene, 300 steps, two attractor points: the forward rollout with the cost
// terms (one line-search trial), the rollout with the backward pass (the gradient) with the
// analytic step products and, as the same-run baseline, with the finite-difference products
// (central: the previous default; forward), and ten iterations of each. Per plan (all clusters):
// with TASKMAP_BENCH_BASKET_MAP naming a map of the humanoid hand on meshes/objects/basket.obj
// (docs/REACHING.md), planGrasp on reaching/scenes/basket_{reference,forward,sideways}.json,
// analytic and finite-difference products, with and without screening the clusters.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>

#include "reaching_bench_setup.hpp"
#include "taskmap/reaching/grasp_planner.hpp"
#include "taskmap/reaching/trajectory_optimizer.hpp"

namespace taskmap {
namespace {

struct Setup {
  std::unique_ptr<bench::PandaScene> scene;
  TrajectoryProblem problem;
  std::vector<Eigen::VectorXd> points;
};

const Setup& setup() {
  static const Setup s = [] {
    Setup out;
    out.scene = bench::pandaInScene(defaultReachScene());
    TrajectoryProblem& p = out.problem;
    p.robot = &out.scene->robot;
    p.collisions = out.scene->collisions.get();
    p.body = out.scene->robot.palmBody();
    p.reference = out.scene->object;
    p.q0 = out.scene->q0;
    p.frame = bench::sideGrasp().linear();
    const Eigen::Matrix<double, 6, 1> x0 = startTaskVariables(p);
    Eigen::Matrix<double, 6, 1> target = Eigen::Matrix<double, 6, 1>::Zero();
    target.head<3>() = bench::sideGrasp().translation();
    out.points = {0.5 * (x0 + target), target};
    return out;
  }();
  return s;
}

/// The problem with the step products taken by `mode`: 0 analytic, 1 central differences,
/// 2 forward differences.
TrajectoryProblem withStepProducts(const TrajectoryProblem& base, int mode) {
  TrajectoryProblem p = base;
  p.step_derivative = mode == 0 ? StepDerivative::kAnalytic : StepDerivative::kFiniteDifferences;
  p.step_jacobian_differences =
      mode == 1 ? FiniteDifferences::kCentral : FiniteDifferences::kForward;
  if (mode == 2) p.step_jacobian_epsilon = 1e-8;
  return p;
}

const char* modeName(int mode) {
  return mode == 0 ? "analytic" : mode == 1 ? "central differences" : "forward differences";
}

void BM_RolloutAndCost(benchmark::State& state) {
  const Setup& s = setup();
  for (auto _ : state) benchmark::DoNotOptimize(evaluateTrajectory(s.problem, s.points, false));
  state.counters["steps"] = s.problem.reach.steps;
}
BENCHMARK(BM_RolloutAndCost)->Unit(benchmark::kMillisecond);

void BM_RolloutCostAndGradient(benchmark::State& state) {
  const Setup& s = setup();
  const TrajectoryProblem p = withStepProducts(s.problem, static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(evaluateTrajectory(p, s.points, true));
  state.SetLabel(modeName(static_cast<int>(state.range(0))));
  state.counters["steps"] = p.reach.steps;
}
BENCHMARK(BM_RolloutCostAndGradient)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

void BM_TenIterations(benchmark::State& state) {
  const Setup& s = setup();
  const TrajectoryProblem p = withStepProducts(s.problem, static_cast<int>(state.range(0)));
  TrajectoryOptimizerOptions o;
  o.max_iterations = 10;
  o.relative_tolerance = 0.0;
  int iterations = 0;
  for (auto _ : state) {
    const TrajectoryOptimization r = optimizeTrajectory(p, s.points, o);
    iterations += r.iterations;
    benchmark::DoNotOptimize(r.cost.total);
  }
  state.SetLabel(modeName(static_cast<int>(state.range(0))));
  state.counters["iterations"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_TenIterations)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

/// planGrasp over every reachable cluster of the basket map: args (step products: 0 analytic,
/// 1 central differences; screen_iterations; scene: 0 reference, 1 forward, 2 sideways).
void BM_PlanAllClusters(benchmark::State& state) {
  const char* path = std::getenv("TASKMAP_BENCH_BASKET_MAP");
  if (!path) {
    state.SkipWithError("set TASKMAP_BENCH_BASKET_MAP to a basket map of the humanoid hand");
    return;
  }
  static const TaskMap map = TaskMap::load(path);
  const char* scenes[] = {"reference", "forward", "sideways"};
  const std::unique_ptr<bench::PandaScene> scene = bench::pandaInScene(
      loadReachScene(std::string(TASKMAP_SOURCE_DIR) + "/reaching/scenes/basket_" +
                     scenes[state.range(2)] + ".json"));
  TrajectoryProblem base;
  base.robot = &scene->robot;
  base.collisions = scene->collisions.get();
  base.body = scene->robot.palmBody();
  base.reference = scene->object;
  base.q0 = scene->q0;
  const TrajectoryProblem p = withStepProducts(base, static_cast<int>(state.range(0)));
  GraspPlanOptions o;
  o.all_clusters = true;
  o.screen_iterations = static_cast<int>(state.range(1));
  int iterations = 0, clusters = 0, chosen = -1;
  double cost = 0.0;
  for (auto _ : state) {
    const GraspPlan plan = planGrasp(p, map, o);
    clusters = static_cast<int>(plan.plans.size());
    for (const ClusterPlan& c : plan.plans) iterations += c.optimization.iterations;
    chosen = plan.best >= 0 ? plan.plans[plan.best].grasp_cluster : -1;
    cost = plan.best >= 0 ? plan.plans[plan.best].optimization.cost.total : 0.0;
    benchmark::DoNotOptimize(plan.best);
  }
  state.SetLabel(std::string(modeName(static_cast<int>(state.range(0)))) + ", " +
                 scenes[state.range(2)]);
  state.counters["clusters"] = clusters;
  state.counters["chosen_cluster"] = chosen;
  state.counters["cost"] = cost;
  state.counters["iterations"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_PlanAllClusters)
    ->Args({1, 0, 0})
    ->Args({0, 0, 0})
    ->Args({0, 5, 0})
    ->Args({0, 10, 0})
    ->Args({0, 0, 1})
    ->Args({0, 5, 1})
    ->Args({0, 10, 1})
    ->Args({0, 0, 2})
    ->Args({0, 5, 2})
    ->Args({0, 10, 2})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace taskmap

BENCHMARK_MAIN();
