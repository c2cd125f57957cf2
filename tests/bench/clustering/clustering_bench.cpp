// Single-linkage dendrogram time on clustered, embedded grasp poses, for n = 1e4, 1e5, 1e6,
// and side by side with fastcluster.linkage_vector(method="single") (Debian's
// python3-fastcluster) at n = 2e4 in the same run, with a check that the merge distances
// are identical. Counters: fastcluster_over_ours (wall-time speed-up), fastcluster_over_ours_cpu
// (CPU seconds of all threads: robust when the machine is shared), max_rel_diff of distances.
#include <benchmark/benchmark.h>

#include <time.h>
#include <unistd.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>

#include "taskmap/clustering/clustering.hpp"
#include "taskmap/core/random.hpp"

namespace {

/// n poses in `blobs` Gaussian blobs (1 cm, 0.1 rad) with centres uniform in a 0.3 m cube
/// and uniform orientations, embedded with rho = 0.1 m.
taskmap::PointMatrix clusteredPoses(int n, int blobs, std::uint64_t seed) {
  taskmap::Rng centre_rng(seed, 0);
  std::vector<taskmap::Pose> centres(blobs);
  for (auto& c : centres) {
    c.position = Eigen::Vector3d(centre_rng.uniform(0, 0.3), centre_rng.uniform(0, 0.3),
                                 centre_rng.uniform(0, 0.3));
    c.orientation = centre_rng.rotation();
  }
  taskmap::PointMatrix points(n, taskmap::kEmbeddingDim);
  taskmap::Rng rng(seed, 1);
  for (int i = 0; i < n; ++i) {
    const taskmap::Pose& c = centres[rng.below(blobs)];
    taskmap::Pose p;
    p.position = c.position + 0.01 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    const Eigen::Vector3d w = 0.1 * Eigen::Vector3d(rng.normal(), rng.normal(), rng.normal());
    p.orientation = Eigen::Quaterniond(c.orientation.toRotationMatrix() * taskmap::rotationExp(w));
    points.row(i) = taskmap::embedPose(p, 0.1).transpose();
  }
  return points;
}

std::map<int, double>& ourSeconds() {
  static std::map<int, double> seconds;
  return seconds;
}

/// CPU seconds of the ours (all threads of this process), per n: robust against other load.
std::map<int, double>& ourCpuSeconds() {
  static std::map<int, double> seconds;
  return seconds;
}

double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void BM_SingleLinkage(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const taskmap::PointMatrix points = clusteredPoses(n, 300, 1);
  double total = 0.0;
  double cpu = 0.0;
  int runs = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = processCpuSeconds();
    taskmap::LinkageMatrix z = taskmap::computeLinkage(points, taskmap::Linkage::kSingle);
    cpu += processCpuSeconds() - cpu_start;
    total += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++runs;
    benchmark::DoNotOptimize(z.data());
  }
  ourSeconds()[n] = total / runs;
  ourCpuSeconds()[n] = cpu / runs;
  state.counters["cpu_s_all_threads"] = cpu / runs;
  state.counters["points"] = n;
}
BENCHMARK(BM_SingleLinkage)->Arg(10000)->Arg(20000)->Arg(100000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SingleLinkage)->Arg(1000000)->Iterations(1)->Unit(benchmark::kMillisecond);

// The default method up to 20000 grasps (ClusteringOptions): average linkage, O(n^2) memory
// and time; compare with BM_SingleLinkage at the same n in the same run.
void BM_AverageLinkage(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const taskmap::PointMatrix points = clusteredPoses(n, 300, 1);
  for (auto _ : state) {
    taskmap::LinkageMatrix z = taskmap::computeLinkage(points, taskmap::Linkage::kAverage);
    benchmark::DoNotOptimize(z.data());
  }
  state.counters["points"] = n;
}
BENCHMARK(BM_AverageLinkage)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AverageLinkage)->Arg(20000)->Iterations(1)->Unit(benchmark::kMillisecond);

void writeText(const std::string& path, const Eigen::Ref<const Eigen::MatrixXd>& m) {
  std::ofstream out(path);
  char buf[32];
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    for (Eigen::Index j = 0; j < m.cols(); ++j) {
      std::snprintf(buf, sizeof buf, "%.17g", m(i, j));
      out << (j ? " " : "") << buf;
    }
    out << "\n";
  }
}

/// fastcluster.linkage_vector on the same 2e4 points; time measured inside python around the
/// call only (manual time).
void BM_FastclusterSingle(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const taskmap::PointMatrix points = clusteredPoses(n, 300, 1);
  const taskmap::LinkageMatrix ours = taskmap::computeLinkage(points, taskmap::Linkage::kSingle);
  char dir_template[] = "/tmp/taskmap_bench_XXXXXX";
  const char* dir = mkdtemp(dir_template);
  if (!dir) {
    state.SkipWithError("mkdtemp failed");
    return;
  }
  const std::string base(dir);
  writeText(base + "/points.txt", points);
  writeText(base + "/ours.txt", ours);
  {
    std::ofstream py(base + "/run.py");
    py << "import sys, time, numpy as np, fastcluster\n"
          "X = np.loadtxt(sys.argv[1]); ours = np.loadtxt(sys.argv[2])\n"
          "t = time.perf_counter(); c = time.process_time()\n"
          "Z = fastcluster.linkage_vector(X, method='single')\n"
          "t = time.perf_counter() - t; c = time.process_time() - c\n"
          "rel = np.max(np.abs(Z[:, 2] - ours[:, 2]) / np.maximum(np.abs(Z[:, 2]), 1e-300))\n"
          "open(sys.argv[3], 'w').write('%.9g %.9g %.9g\\n' % (t, rel, c))\n";
  }
  double max_rel = -1.0;
  for (auto _ : state) {
    const std::string cmd = std::string(TASKMAP_PYTHON) + " " + base + "/run.py " + base +
                            "/points.txt " + base + "/ours.txt " + base + "/out.txt";
    if (std::system(cmd.c_str()) != 0) {
      state.SkipWithError("python3 with numpy and fastcluster failed");
      break;
    }
    std::ifstream in(base + "/out.txt");
    double seconds = 0.0;
    double cpu = 0.0;
    in >> seconds >> max_rel >> cpu;
    state.SetIterationTime(seconds);
    const auto it = ourSeconds().find(n);
    if (it != ourSeconds().end()) state.counters["fastcluster_over_ours"] = seconds / it->second;
    const auto cpu_it = ourCpuSeconds().find(n);
    if (cpu_it != ourCpuSeconds().end()) {
      state.counters["fastcluster_over_ours_cpu"] = cpu / cpu_it->second;
    }
  }
  state.counters["max_rel_diff"] = max_rel;
  std::system(("rm -rf " + base).c_str());
}
BENCHMARK(BM_FastclusterSingle)
    ->Arg(20000)
    ->Iterations(3)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
