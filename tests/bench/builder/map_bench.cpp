// Map store and pipeline benchmarks. Compare within one run:
//  - BM_Build/threads:N against BM_Build/threads:1 (parallel speed-up of the pipeline),
//  - BM_WriteMap / BM_ReadMap of a 1000-grasp map against the build time of that map.
// Counters: trials/s, and the share of worker time in sampling, simulation and quality.
#include <unistd.h>

#include <cstdio>
#include <string>

#include <benchmark/benchmark.h>

#include "build_fixtures.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

constexpr auto box = &testing::boxObject;
constexpr auto panda = &testing::pandaHand;

BuildOptions options(int threads, std::uint64_t valid) {
  BuildOptions o;
  o.seed = 1;
  o.valid_target = valid;
  o.threads = threads;
  return o;
}

void BM_Build(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  double trials = 0, sampling = 0, simulation = 0, quality = 0, wall = 0;
  for (auto _ : state) {
    const BuildResult r = buildMap(box(), panda(), options(threads, 40));
    benchmark::DoNotOptimize(r.map.grasps.pose.data());
    trials += static_cast<double>(r.timing.trials_simulated);
    sampling += r.timing.sampling_seconds;
    simulation += r.timing.simulation_seconds;
    quality += r.timing.quality_seconds;
    wall += r.timing.wall_seconds;
  }
  const double work = sampling + simulation + quality;
  state.counters["trials_per_s"] = trials / wall;
  state.counters["sampling_share"] = sampling / work;
  state.counters["simulation_share"] = simulation / work;
  state.counters["quality_share"] = quality / work;
}
BENCHMARK(BM_Build)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

const TaskMapData& thousandGraspMap() {
  static const TaskMapData map = [] {
    BuildOptions o = options(0, 1000);
    o.max_trials = 1000000;
    return buildMap(box(), panda(), o).map;
  }();
  return map;
}

std::string benchPath() {
  return "/tmp/taskmap_map_bench_" + std::to_string(::getpid()) + ".h5";
}

void BM_WriteMap(benchmark::State& state) {
  const TaskMapData& map = thousandGraspMap();
  const std::string path = benchPath();
  for (auto _ : state) writeMap(path, map);
  state.counters["grasps"] = static_cast<double>(map.grasps.size());
  std::remove(path.c_str());
}
BENCHMARK(BM_WriteMap)->Unit(benchmark::kMillisecond);

void BM_ReadMap(benchmark::State& state) {
  const TaskMapData& map = thousandGraspMap();
  const std::string path = benchPath();
  writeMap(path, map);
  for (auto _ : state) benchmark::DoNotOptimize(readMap(path).grasps.pose.data());
  std::remove(path.c_str());
}
BENCHMARK(BM_ReadMap)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace taskmap

BENCHMARK_MAIN();
