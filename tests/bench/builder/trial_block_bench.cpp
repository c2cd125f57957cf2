// What rank 0 of taskmap-mpi spends per block, against what the block cost to simulate (same
// run): BM_RunBlock (simulate 256 trials on one thread) vs BM_DecodeBlock and
// BM_CheckpointAppend (rank 0's service of one returned block) and BM_EncodeBlock (the
// worker's). Counter time_per_trial: seconds of wall time per trial (CPU time in the CPU column).
#include <unistd.h>

#include <string>

#include <benchmark/benchmark.h>

#include "build_fixtures.hpp"
#include "taskmap/builder/build_checkpoint.hpp"
#include "taskmap/builder/trial_block.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {
namespace {

constexpr std::uint64_t kBlock = 256;

const ObjectModel& basket() {
  static const ObjectModel object =
      ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/basket.obj");
  return object;
}
const HandModel& barrett() {
  static const HandModel hand =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  return hand;
}

BuildOptions options() {
  BuildOptions o;
  o.threads = 1;
  o.stored =
      StoredGrasps::kAllCompleted;  // more stored grasps than a real build: an upper bound on bytes
  return o;
}

const TrialBlock& block() {
  static const TrialBlock b = [] {
    TrialRunner runner(basket(), barrett(), options());
    TrialBlock out;
    runner.run(0, kBlock, &out);
    return out;
  }();
  return b;
}

void perTrial(benchmark::State& state) {
  state.counters["time_per_trial"] = benchmark::Counter(
      static_cast<double>(state.iterations() * kBlock),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::OneK::kIs1000);
}

void BM_RunBlock(benchmark::State& state) {
  TrialRunner runner(basket(), barrett(), options());
  std::uint64_t first = 0;
  for (auto _ : state) {
    TrialBlock b;
    runner.run(first, first + kBlock, &b);
    first += kBlock;
    benchmark::DoNotOptimize(b.trials.data());
  }
  perTrial(state);
}
BENCHMARK(BM_RunBlock)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_EncodeBlock(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(encodeTrialBlock(block()).data());
  state.counters["bytes"] = static_cast<double>(encodeTrialBlock(block()).size());
  perTrial(state);
}
BENCHMARK(BM_EncodeBlock)->Unit(benchmark::kMicrosecond);

void BM_DecodeBlock(benchmark::State& state) {
  const std::string bytes = encodeTrialBlock(block());
  const std::size_t joints = barrett().jointNames().size();
  for (auto _ : state) benchmark::DoNotOptimize(decodeTrialBlock(bytes, joints, "bench"));
  perTrial(state);
}
BENCHMARK(BM_DecodeBlock)->Unit(benchmark::kMicrosecond);

void BM_CheckpointAppend(benchmark::State& state) {
  const std::string path = "/tmp/taskmap_ckpt_bench_" + std::to_string(::getpid());
  BuildCheckpoint checkpoint(path, buildIdentity(basket(), barrett(), options(), kBlock),
                             barrett().jointNames().size());
  for (auto _ : state) checkpoint.append(block());
  checkpoint.remove();
  perTrial(state);
}
BENCHMARK(BM_CheckpointAppend)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace taskmap

BENCHMARK_MAIN();
