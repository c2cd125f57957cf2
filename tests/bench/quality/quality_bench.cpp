// Speed of evaluateGrasp: microseconds per grasp for 2, 3, 4, 6 and 10 contacts with GraspIt!'s
// m = 8 cone edges, on 1 and 2 threads (real time, so items_per_second shows the scaling).
// Baseline in the same run: the same call serialised under one global mutex, as GraspIt! and
// Simox do with their qhull calls. Ratios: Threads(2) vs Threads(1) items_per_second of
// BM_EvaluateGrasp (our scaling) against the same ratio of BM_EvaluateGraspGlobalMutex.
#include <mutex>
#include <vector>

#include <benchmark/benchmark.h>

#include "quality_fixtures.hpp"
#include "taskmap/quality/grasp_quality.hpp"

namespace {

using taskmap::Contact;

constexpr int kSets = 64;

/// kSets random grasps of n contacts on the 10 x 6 x 4 cm test ellipsoid (fixed seed).
const std::vector<std::vector<Contact>>& graspSets(int n) {
  static std::vector<std::vector<std::vector<Contact>>> cache(16);
  static std::once_flag once[16];
  std::call_once(once[n], [n] {
    for (int s = 0; s < kSets; ++s) {
      taskmap::Rng rng(77, static_cast<std::uint64_t>(n * 1000 + s));
      cache[n].push_back(taskmap::testing::randomContacts(rng, n, 0.1));
    }
  });
  return cache[n];
}

std::mutex global_qhull_mutex;

void runGrasps(benchmark::State& state, bool global_lock) {
  const int n = static_cast<int>(state.range(0));
  const auto& sets = graspSets(n);
  std::size_t i = static_cast<std::size_t>(state.thread_index()) * 17;
  int closures = 0;
  for (auto _ : state) {
    const auto& c = sets[i++ % sets.size()];
    taskmap::QualityResult r;
    if (global_lock) {
      std::lock_guard<std::mutex> lock(global_qhull_mutex);
      r = taskmap::evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05);
    } else {
      r = taskmap::evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05);
    }
    closures += r.force_closure;
    benchmark::DoNotOptimize(r.epsilon);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["closure_rate"] =
      benchmark::Counter(static_cast<double>(closures) / static_cast<double>(state.iterations()),
                         benchmark::Counter::kAvgThreads);
}

void BM_EvaluateGrasp(benchmark::State& state) {
  runGrasps(state, false);
}
void BM_EvaluateGraspGlobalMutex(benchmark::State& state) {
  runGrasps(state, true);
}

BENCHMARK(BM_EvaluateGrasp)
    ->Arg(2)
    ->Arg(3)
    ->Arg(4)
    ->Arg(6)
    ->Arg(10)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime()
    ->Threads(1)
    ->Threads(2);
BENCHMARK(BM_EvaluateGraspGlobalMutex)
    ->Arg(4)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime()
    ->Threads(1)
    ->Threads(2);

}  // namespace

BENCHMARK_MAIN();
