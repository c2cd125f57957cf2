// Cost of verifying a map's seal (mapstore/SCHEMA.md, "Seal") on a 10^5-grasp map. Compare
// within one run:
//  - BM_ReadMap: readMap as every reader calls it (seal check, then HDF5 parse from memory),
//  - BM_VerifySeal: the seal check alone (read the file, SHA-256, compare; white-box call of
//    mapstore/src/map_seal.hpp), i.e. what readMap would save without verification.
// Load time without verification = BM_ReadMap - BM_VerifySeal; the reported overhead ratio is
// BM_ReadMap / (BM_ReadMap - BM_VerifySeal).
// The map: the 20 grasps of tests/data/maps/box_barrett.h5 tiled to 10^5 rows with small
// position and epsilon noise (so compression sees realistic, non-repeating data).
#include <unistd.h>

#include <cstdio>
#include <string>

#include <benchmark/benchmark.h>

#include "map_seal.hpp"
#include "taskmap/core/random.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

constexpr std::size_t kGrasps = 100000;

TaskMapData tiledMap() {
  const TaskMapData src = readMap(std::string(TEST_DATA_DIR) + "/maps/box_barrett.h5");
  const MapGrasps& s = src.grasps;
  const std::size_t n0 = s.size();
  TaskMapData m = src;
  m.clustering.reset();
  MapGrasps& g = m.grasps;
  const auto n = static_cast<Eigen::Index>(kGrasps);
  g.pose.resize(n, 7);
  g.joints.resize(n, s.joints.cols());
  g.force_closure.clear();
  g.epsilon.clear();
  g.volume.clear();
  g.contact_offsets.assign(1, 0);
  std::vector<Eigen::Index> rows;
  Rng rng(5, 0);
  for (std::size_t i = 0; i < kGrasps; ++i) {
    const std::size_t k = i % n0;
    const auto r = static_cast<Eigen::Index>(i);
    g.pose.row(r) = s.pose.row(static_cast<Eigen::Index>(k));
    for (int c = 0; c < 3; ++c) g.pose(r, c) += 1e-4 * (rng.uniform() - 0.5);
    g.joints.row(r) = s.joints.row(static_cast<Eigen::Index>(k));
    g.force_closure.push_back(s.force_closure[k]);
    g.epsilon.push_back(s.epsilon[k] * (1.0 + 0.01 * rng.uniform()));
    g.volume.push_back(s.volume[k]);
    for (auto c = s.contact_offsets[k]; c < s.contact_offsets[k + 1]; ++c)
      rows.push_back(static_cast<Eigen::Index>(c));
    g.contact_offsets.push_back(static_cast<std::int64_t>(rows.size()));
  }
  const auto m_rows = static_cast<Eigen::Index>(rows.size());
  g.contact_points.resize(m_rows, 3);
  g.contact_normals.resize(m_rows, 3);
  g.contact_depths.clear();
  g.contact_links.clear();
  for (Eigen::Index j = 0; j < m_rows; ++j) {
    const Eigen::Index c = rows[static_cast<std::size_t>(j)];
    g.contact_points.row(j) = s.contact_points.row(c);
    for (int d = 0; d < 3; ++d) g.contact_points(j, d) += 1e-4 * (rng.uniform() - 0.5);
    g.contact_normals.row(j) = s.contact_normals.row(c);
    g.contact_depths.push_back(s.contact_depths[static_cast<std::size_t>(c)]);
    g.contact_links.push_back(s.contact_links[static_cast<std::size_t>(c)]);
  }
  m.sampling.outcomes = {{"force_closure", kGrasps}};
  m.sampling.trials = kGrasps;
  return m;
}

const std::string& mapPath() {
  static const std::string path = [] {
    const std::string p = "/tmp/taskmap_seal_bench_" + std::to_string(::getpid()) + ".h5";
    writeMap(p, tiledMap());
    return p;
  }();
  return path;
}

void BM_ReadMap(benchmark::State& state) {
  const std::string& path = mapPath();
  for (auto _ : state) benchmark::DoNotOptimize(readMap(path).grasps.pose.data());
  state.counters["grasps"] = static_cast<double>(kGrasps);
}
BENCHMARK(BM_ReadMap)->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_VerifySeal(benchmark::State& state) {
  const std::string& path = mapPath();
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::string b = seal::readVerified(path);
    bytes = b.size();
    benchmark::DoNotOptimize(b.data());
  }
  state.counters["file_MiB"] = static_cast<double>(bytes) / (1024.0 * 1024.0);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
}
BENCHMARK(BM_VerifySeal)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace
}  // namespace taskmap

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  std::remove(taskmap::mapPath().c_str());
  return 0;
}
