// ObjectModel queries on the reference objects against brute-force baselines measured in the
// same run: contains() (BVH ray parity) vs the winding number over all triangles, and
// distanceToSurface() (BVH) vs the closest point over all triangles. Compare the ratios.
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "taskmap/meshes/object_model.hpp"

namespace {

using taskmap::ObjectModel;

const ObjectModel& model(int index) {
  static const std::vector<ObjectModel> models = [] {
    std::vector<ObjectModel> m;
    for (const char* name : {"box", "sphere", "mug", "basket"}) {
      m.push_back(ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/" + name + ".obj"));
    }
    return m;
  }();
  return models[static_cast<std::size_t>(index)];
}

std::vector<Eigen::Vector3d> queryPoints(const ObjectModel& m) {
  taskmap::Rng rng(1, 0);
  const auto& mp = m.massProperties();
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 1024; ++i) {
    points.emplace_back(rng.uniform(mp.bounds_min.x(), mp.bounds_max.x()),
                        rng.uniform(mp.bounds_min.y(), mp.bounds_max.y()),
                        rng.uniform(mp.bounds_min.z(), mp.bounds_max.z()));
  }
  return points;
}

double windingNumber(const taskmap::TriangleMesh& mesh, const Eigen::Vector3d& p) {
  double total = 0;
  for (const auto& f : mesh.faces) {
    const Eigen::Vector3d a = mesh.vertices[f[0]] - p, b = mesh.vertices[f[1]] - p,
                          c = mesh.vertices[f[2]] - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    total += 2 * std::atan2(a.dot(b.cross(c)),
                            la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
  }
  return total / (4 * M_PI);
}

void BM_ContainsBvh(benchmark::State& state) {
  const ObjectModel& m = model(static_cast<int>(state.range(0)));
  const auto points = queryPoints(m);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(m.contains(points[i++ % points.size()]));
  state.SetLabel(m.name() + " " + std::to_string(m.mesh().faces.size()) + " faces");
}

void BM_ContainsBruteForceWinding(benchmark::State& state) {
  const ObjectModel& m = model(static_cast<int>(state.range(0)));
  const auto points = queryPoints(m);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(windingNumber(m.mesh(), points[i++ % points.size()]) > 0.5);
  }
  state.SetLabel(m.name() + " baseline");
}

void BM_DistanceBvh(benchmark::State& state) {
  const ObjectModel& m = model(static_cast<int>(state.range(0)));
  const auto points = queryPoints(m);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(m.distanceToSurface(points[i++ % points.size()]));
  state.SetLabel(m.name());
}

void BM_SampleInside(benchmark::State& state) {
  const ObjectModel& m = model(static_cast<int>(state.range(0)));
  taskmap::Rng rng(2, 0);
  for (auto _ : state) benchmark::DoNotOptimize(m.sampleInside(rng));
  state.SetLabel(m.name());
}

void BM_SampleSurface(benchmark::State& state) {
  const ObjectModel& m = model(static_cast<int>(state.range(0)));
  taskmap::Rng rng(3, 0);
  for (auto _ : state) benchmark::DoNotOptimize(m.sampleSurface(rng));
  state.SetLabel(m.name());
}

BENCHMARK(BM_ContainsBvh)->DenseRange(0, 3);
BENCHMARK(BM_ContainsBruteForceWinding)->DenseRange(0, 3);
BENCHMARK(BM_DistanceBvh)->DenseRange(0, 3);
BENCHMARK(BM_SampleInside)->DenseRange(0, 3);
BENCHMARK(BM_SampleSurface)->DenseRange(0, 3);

}  // namespace

BENCHMARK_MAIN();
