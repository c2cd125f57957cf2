// Grasps validated per CPU-second: the hold test on the stored grasps of small maps (panda jaws
// on the box, barrett on the cylinder), with contact patches (the default) against one contact
// point per shape in the same process (the ratio is what patches cost); the settled stop (the
// default) against the full pushes of the published protocol; and the robust test (every
// variant, the default build's test) against the nominal protocol.
#include <benchmark/benchmark.h>

#include <string>
#include <utility>

#include "build_fixtures.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/validate/hold_test.hpp"
#include "taskmap/validate/robust_hold.hpp"

namespace taskmap {
namespace {

struct Case {
  HandModel hand;
  ObjectModel object;
  TaskMapData map;
};

// The stored grasps of a small default build (16 grasps, one thread) of `object` with `hand`.
Case makeCase(HandModel hand, ObjectModel object) {
  BuildOptions o;
  o.valid_target = 16;
  o.threads = 1;
  Case k{std::move(hand), std::move(object), {}};
  k.map = buildMap(k.object, k.hand, o).map;
  return k;
}

const Case& pandaBox() {
  static const Case c = makeCase(testing::pandaHand(), testing::boxObject());
  return c;
}

const Case& barrettCylinder() {
  static const Case c =
      makeCase(HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf"),
               ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/cylinder.obj"));
  return c;
}

void run(benchmark::State& state, const Case& c) {
  HoldTestOptions o;
  o.contact_patch = state.range(0) == 0 ? 0.0 : 0.01;
  const HoldTester tester(c.hand, c.object, o);
  std::size_t i = 0, holds = 0, n = 0;
  for (auto _ : state) {
    const std::size_t g = i++ % c.map.grasps.size();
    const Eigen::VectorXd q = c.map.grasps.joints.row(static_cast<Eigen::Index>(g)).transpose();
    const HoldResult r = tester.test(c.map.grasps.poseAt(g), q);
    holds += r.holds;
    ++n;
    benchmark::DoNotOptimize(r);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(n));
  state.counters["hold_rate"] = n ? static_cast<double>(holds) / static_cast<double>(n) : 0.0;
}

// Arg 0: every push its whole 2 s (the protocol as published); 1: pushes end once settled.
void runSettle(benchmark::State& state, const Case& c) {
  HoldTestOptions o;
  o.settle_stop = state.range(0) == 1;
  const HoldTester tester(c.hand, c.object, o);
  std::size_t i = 0, holds = 0, n = 0;
  long long steps = 0;
  for (auto _ : state) {
    const std::size_t g = i++ % c.map.grasps.size();
    const Eigen::VectorXd q = c.map.grasps.joints.row(static_cast<Eigen::Index>(g)).transpose();
    const HoldResult r = tester.test(c.map.grasps.poseAt(g), q);
    holds += r.holds;
    steps += r.steps;
    ++n;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(n));
  state.counters["hold_rate"] = n ? static_cast<double>(holds) / static_cast<double>(n) : 0.0;
  state.counters["steps"] = n ? static_cast<double>(steps) / static_cast<double>(n) : 0.0;
}

// The robust test of every variant (all_variants) per grasp: what a robust label costs.
void runRobust(benchmark::State& state, const Case& c) {
  RobustHoldOptions o;
  o.all_variants = true;
  const RobustHoldTester tester(c.hand, c.object, o);
  std::size_t i = 0, robust = 0, n = 0;
  for (auto _ : state) {
    const std::size_t g = i++ % c.map.grasps.size();
    const Eigen::VectorXd q = c.map.grasps.joints.row(static_cast<Eigen::Index>(g)).transpose();
    robust += tester.test(c.map.grasps.poseAt(g), q).robust;
    ++n;
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(n));
  state.counters["robust_rate"] = n ? static_cast<double>(robust) / static_cast<double>(n) : 0.0;
}

void BM_SettleBarrettCylinder(benchmark::State& state) {
  runSettle(state, barrettCylinder());
}
void BM_RobustBarrettCylinder(benchmark::State& state) {
  runRobust(state, barrettCylinder());
}
BENCHMARK(BM_SettleBarrettCylinder)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(32);
BENCHMARK(BM_RobustBarrettCylinder)->Unit(benchmark::kMillisecond)->Iterations(16);

void BM_PandaBox(benchmark::State& state) {
  run(state, pandaBox());
}
void BM_BarrettCylinder(benchmark::State& state) {
  run(state, barrettCylinder());
}
BENCHMARK(BM_PandaBox)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(32);
BENCHMARK(BM_BarrettCylinder)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(32);

}  // namespace
}  // namespace taskmap

BENCHMARK_MAIN();
