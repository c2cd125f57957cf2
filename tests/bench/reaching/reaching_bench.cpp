// Control-step cost of the reaching stage on the Panda with the humanoid hand in the default
// scene (table, object): kinematics alone, the collision cost with its gradient, one full IK
// step (FK + Jacobians + collision pairs + weighted pseudo-inverse + null space), and a whole
// 300-step rollout. Baseline in the same run: KDL's FK + Jacobian of the same chain.
#include <benchmark/benchmark.h>

#include "reaching_bench_setup.hpp"
#include "taskmap/reaching/attractor.hpp"

#ifdef TASKMAP_HAVE_KDL
#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#endif

namespace taskmap {
namespace {

struct Setup {
  std::unique_ptr<bench::PandaScene> scene;
  RobotModel& robot;
  CollisionModel* collisions;
  int object;
  Eigen::Isometry3d target = bench::sideGrasp();
  Eigen::VectorXd q0;
  std::vector<Eigen::VectorXd> trajectory;  // configurations of a rollout, cycled through

  explicit Setup(std::unique_ptr<bench::PandaScene> s)
      : scene(std::move(s)),
        robot(scene->robot),
        collisions(scene->collisions.get()),
        object(scene->object),
        q0(scene->q0) {
    trajectory = reach(robot, collisions, robot.palmBody(), object, target, q0, ReachOptions{}).q;
  }
};

const Setup& setup() {
  static const Setup s(bench::pandaInScene(defaultReachScene()));
  return s;
}

void BM_FkAndPalmJacobian(benchmark::State& state) {
  const Setup& s = setup();
  Kinematics kin(s.robot);
  size_t k = 0;
  for (auto _ : state) {
    kin.update(s.trajectory[k++ % s.trajectory.size()]);
    benchmark::DoNotOptimize(kin.jacobian(s.robot.palmBody()));
  }
}
BENCHMARK(BM_FkAndPalmJacobian)->Unit(benchmark::kMicrosecond);

void BM_CollisionCostAndGradient(benchmark::State& state) {
  const Setup& s = setup();
  Kinematics kin(s.robot);
  Eigen::VectorXd g;
  size_t k = 0;
  for (auto _ : state) {
    state.PauseTiming();
    kin.update(s.trajectory[k++ % s.trajectory.size()]);
    state.ResumeTiming();
    benchmark::DoNotOptimize(s.collisions->cost(kin, &g));
  }
  state.counters["pairs"] = static_cast<double>(s.collisions->pairs().size());
}
BENCHMARK(BM_CollisionCostAndGradient)->Unit(benchmark::kMicrosecond);

void BM_ControlStep(benchmark::State& state) {
  // One control step as in reach(): FK, task Jacobians and errors, collision pairs with
  // gradient, weighted pseudo-inverse with null-space projection, integration.
  const Setup& s = setup();
  const ResolvedRateIK ik(s.robot,
                          {{TaskKind::kPosition, s.robot.palmBody(), s.object, -1},
                           {TaskKind::kOrientation, s.robot.palmBody(), s.object, -1}},
                          s.collisions, IkOptions{});
  Kinematics kin(s.robot);
  std::vector<TaskGoal> goals(2);
  goals[0].position = s.target.translation();
  goals[1].rotation = s.target.linear();
  size_t k = 0;
  for (auto _ : state) {
    kin.update(s.trajectory[k++ % s.trajectory.size()]);
    benchmark::DoNotOptimize(ik.step(kin, goals, 0.01));
  }
  state.counters["pairs"] = static_cast<double>(s.collisions->pairs().size());
}
BENCHMARK(BM_ControlStep)->Unit(benchmark::kMicrosecond);

void BM_Rollout300Steps(benchmark::State& state) {
  const Setup& s = setup();
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        reach(s.robot, s.collisions, s.robot.palmBody(), s.object, s.target, s.q0, ReachOptions{}));
  }
}
BENCHMARK(BM_Rollout300Steps)->Unit(benchmark::kMillisecond);

#ifdef TASKMAP_HAVE_KDL
void BM_KdlFkAndJacobian(benchmark::State& state) {
  // Baseline: the same chain (base to palm) in KDL, built from our model's joint frames.
  const Setup& s = setup();
  KDL::Chain chain;
  const auto frame = [](const Eigen::Isometry3d& t) {
    KDL::Frame f;
    for (int r = 0; r < 3; ++r) {
      f.p(r) = t.translation()[r];
      for (int c = 0; c < 3; ++c) f.M(r, c) = t.linear()(r, c);
    }
    return f;
  };
  std::vector<int> path;
  for (int b = s.robot.palmBody(); b >= 0; b = s.robot.bodies()[b].parent)
    path.insert(path.begin(), b);
  for (int b : path) {
    const RobotBody& body = s.robot.bodies()[b];
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), frame(body.origin)));
    if (body.dof >= 0)
      chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ), KDL::Frame::Identity()));
  }
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jac(chain);
  KDL::JntArray q(7);
  KDL::Frame f;
  KDL::Jacobian j(7);
  size_t k = 0;
  for (auto _ : state) {
    q.data = s.trajectory[k++ % s.trajectory.size()];
    fk.JntToCart(q, f);
    jac.JntToJac(q, j);
    benchmark::DoNotOptimize(j.data.data());
  }
}
BENCHMARK(BM_KdlFkAndJacobian)->Unit(benchmark::kMicrosecond);
#endif

}  // namespace
}  // namespace taskmap

BENCHMARK_MAIN();
