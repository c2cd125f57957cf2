// Grasps validated per CPU-second: the hold test on the stored grasps of small maps (panda jaws
// on the box, barrett on the cylinder), with contact patches (the default) against one contact
// point per shape in the same process (the ratio is what patches cost).
#include <benchmark/benchmark.h>

#include <string>
#include <utility>

#include "build_fixtures.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/validate/hold_test.hpp"

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
