// Speed of evaluateGrasp: microseconds per grasp for 2, 3, 4, 6 and 10 contacts with GraspIt!'s
// m = 8 cone edges, on 1 and 2 threads (real time, so items_per_second shows the scaling).
//  - BM_EvaluateGrasp: the default (force closure, epsilon, and the volume of force-closure
//    grasps, which needs the whole hull);
//  - BM_EvaluateGraspEpsilonOnly: VolumeMode::kNever (force closure and epsilon only: Zheng's
//    refinement inserts only the wrenches it needs);
//  - BM_QhullBaseline: the previous method on the same grasps (wrench set, then the whole hull
//    with reentrant qhull, volume included), serialised under one global mutex as GraspIt! and
//    Simox do (BM_QhullBaselineGlobalMutex) or not (BM_QhullBaseline).
// The summary at the end prints ratios against the baselines measured in this same run.
#include <cstdio>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "quality_fixtures.hpp"
#include "taskmap/quality/grasp_quality.hpp"
#include "taskmap/quality/wrench_hull.hpp"

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

enum class Method { kDefault, kEpsilonOnly, kQhull, kQhullGlobalMutex };

std::mutex global_qhull_mutex;

taskmap::QualityResult qhullQuality(const std::vector<Contact>& c) {
  taskmap::QualityResult r;
  taskmap::summarizeHull(
      taskmap::wrenchHull(taskmap::contactWrenches(c, Eigen::Vector3d::Zero(), 0.05)), r);
  return r;
}

void runGrasps(benchmark::State& state, Method method) {
  const int n = static_cast<int>(state.range(0));
  const auto& sets = graspSets(n);
  std::size_t i = static_cast<std::size_t>(state.thread_index()) * 17;
  taskmap::QualityOptions epsilon_only;
  epsilon_only.volume = taskmap::VolumeMode::kNever;
  int closures = 0;
  for (auto _ : state) {
    const auto& c = sets[i++ % sets.size()];
    taskmap::QualityResult r;
    switch (method) {
      case Method::kDefault:
        r = taskmap::evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05);
        break;
      case Method::kEpsilonOnly:
        r = taskmap::evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05, epsilon_only);
        break;
      case Method::kQhull:
        r = qhullQuality(c);
        break;
      case Method::kQhullGlobalMutex: {
        std::lock_guard<std::mutex> lock(global_qhull_mutex);
        r = qhullQuality(c);
        break;
      }
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
  runGrasps(state, Method::kDefault);
}
void BM_EvaluateGraspEpsilonOnly(benchmark::State& state) {
  runGrasps(state, Method::kEpsilonOnly);
}
void BM_QhullBaseline(benchmark::State& state) {
  runGrasps(state, Method::kQhull);
}
void BM_QhullBaselineGlobalMutex(benchmark::State& state) {
  runGrasps(state, Method::kQhullGlobalMutex);
}

void contactCounts(benchmark::internal::Benchmark* b) {
  for (int n : {2, 3, 4, 6, 10}) b->Arg(n);
  b->Unit(benchmark::kMicrosecond)->UseRealTime()->Threads(1)->Threads(2);
}
BENCHMARK(BM_EvaluateGrasp)->Apply(contactCounts);
BENCHMARK(BM_EvaluateGraspEpsilonOnly)->Apply(contactCounts);
BENCHMARK(BM_QhullBaseline)->Apply(contactCounts);
BENCHMARK(BM_QhullBaselineGlobalMutex)
    ->Arg(4)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime()
    ->Threads(1)
    ->Threads(2);

/// Console output plus the real time per grasp of every run, keyed by run name.
class Collector : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.run_type == Run::RT_Iteration) {
        // Per-grasp wall time: with n threads, n grasps run at once.
        const double items = r.counters.count("items_per_second")
                                 ? static_cast<double>(r.counters.at("items_per_second"))
                                 : 0.0;
        us[r.benchmark_name()] = items > 0.0 ? 1e6 / items : 0.0;
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }
  std::map<std::string, double> us;  ///< microseconds of wall time per grasp (throughput)
};

double get(const Collector& c, const std::string& name) {
  const auto it = c.us.find(name);
  return it == c.us.end() ? 0.0 : it->second;
}

void printSummary(const Collector& c) {
  std::printf("\nsummary (one thread: us per grasp; ratio = qhull baseline / ours, same run):\n");
  for (int n : {2, 3, 4, 6, 10}) {
    const std::string arg = "/" + std::to_string(n) + "/real_time/threads:1";
    const double eps = get(c, "BM_EvaluateGraspEpsilonOnly" + arg);
    const double def = get(c, "BM_EvaluateGrasp" + arg);
    const double qh = get(c, "BM_QhullBaseline" + arg);
    if (eps <= 0 || def <= 0 || qh <= 0) continue;
    std::printf(
        "  %2d contacts: epsilon only %8.1f us (%6.1fx), with FC volume %8.1f us (%6.1fx), "
        "qhull %8.1f us\n",
        n, eps, qh / eps, def, qh / def, qh);
  }
  std::printf("scaling (throughput 2 threads / 1 thread):\n");
  for (const char* name : {"BM_EvaluateGraspEpsilonOnly/4", "BM_EvaluateGrasp/4",
                           "BM_QhullBaseline/4", "BM_QhullBaselineGlobalMutex/4"}) {
    const double one = get(c, std::string(name) + "/real_time/threads:1");
    const double two = get(c, std::string(name) + "/real_time/threads:2");
    if (one > 0 && two > 0) std::printf("  %-32s %.2fx\n", name, one / two);
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  Collector collector;
  benchmark::RunSpecifiedBenchmarks(&collector);
  printSummary(collector);
  benchmark::Shutdown();
  return 0;
}
