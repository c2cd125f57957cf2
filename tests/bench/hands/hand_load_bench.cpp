// Hand loading with and without the convex decomposition of non-convex collision meshes
// (meshes/hands/README.md), each against its hull-only baseline in the same run: the real Franka
// hand (convex palm: the default keeps the hull; convex_tolerance 0 forces the decomposition),
// and a link whose mesh is the 16k-face YCB banana (simplified to 600 faces, 125 exact pieces
// merged to 16), and one whose mesh is the YCB mug scan (not closed, self-intersecting: its alpha
// wrap is decomposed). Counters: convex shapes, volume of the pieces over the mesh volume (0 when
// the mesh is open).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "taskmap/hands/hand_model.hpp"

namespace {

namespace fs = std::filesystem;
using taskmap::HandModel;

/// A hand folder in the temp directory: `urdf` text and a sidecar with `collision` options.
std::string writeHand(const std::string& tag, const std::string& urdf, const std::string& sidecar) {
  const fs::path dir = fs::temp_directory_path() / ("taskmap_hand_load_bench_" + tag);
  fs::create_directories(dir);
  std::ofstream(dir / "hand.urdf") << urdf;
  std::ofstream(dir / "hand.hand.json") << sidecar;
  return (dir / "hand.urdf").string();
}

std::string frankaHand(const std::string& tag, const std::string& collision) {
  const std::string src = std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/";
  std::ifstream in(src + "franka_hand.urdf");
  std::string urdf((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "meshes/collision/hand.stl";
  urdf.replace(urdf.find(from), from.size(), src + from);
  std::ifstream js(src + "franka_hand.hand.json");
  std::string sidecar((std::istreambuf_iterator<char>(js)), std::istreambuf_iterator<char>());
  sidecar.insert(sidecar.find('{') + 1, "\"collision\": " + collision + ",");
  return writeHand(tag, urdf, sidecar);
}

std::string objectLink(const std::string& tag, const std::string& object,
                       const std::string& collision) {
  const std::string urdf =
      "<robot name=\"banana_link\"><link name=\"base\"><collision><geometry><box size=\"0.2 0.2 "
      "0.02\"/></geometry></collision></link><link name=\"finger\"><collision><geometry><mesh "
      "filename=\"" +
      std::string(TEST_DATA_DIR) + "/real/objects/" + object +
      ".obj\"/></geometry></collision></link><joint name=\"j\" "
      "type=\"prismatic\"><parent link=\"base\"/><child link=\"finger\"/><origin xyz=\"0 0 "
      "0.1\"/><axis xyz=\"1 0 0\"/><limit lower=\"0\" upper=\"0.05\" effort=\"1\" "
      "velocity=\"1\"/></joint></robot>";
  return writeHand(tag, urdf,
                   "{\"palm_link\": \"base\", \"approach_axis\": [0, 0, 1], \"closing\": "
                   "[{\"joint\": \"j\", \"toward\": \"upper\"}], \"squeeze\": 0.0005, "
                   "\"fingers\": {\"a\": [\"finger\"]}, \"collision\": " +
                       collision + "}");
}

void load(benchmark::State& state, const std::string& urdf) {
  for (auto _ : state) {
    const HandModel h = HandModel::load(urdf);
    benchmark::DoNotOptimize(h.links().size());
  }
  const HandModel h = HandModel::load(urdf);
  double pieces = 0.0, ratio = 0.0;
  for (const auto& m : h.collisionMeshes()) {
    pieces += m.pieces;
    ratio = m.mesh_volume > 0.0 ? m.pieces_volume / m.mesh_volume : 0.0;
  }
  state.counters["pieces"] = pieces;
  state.counters["pieces_over_mesh_volume"] = ratio;
}

void BM_FrankaHull(benchmark::State& s) {
  load(s, frankaHand("franka_hull", "{\"decompose\": false}"));
}
void BM_FrankaDefault(benchmark::State& s) {
  load(s, frankaHand("franka_default", "{}"));
}
void BM_FrankaForcedDecomposition(benchmark::State& s) {
  load(s, frankaHand("franka_forced", "{\"convex_tolerance\": 0}"));
}
void BM_BananaLinkHull(benchmark::State& s) {
  load(s, objectLink("banana_hull", "ycb_011_banana", "{\"decompose\": false}"));
}
void BM_BananaLinkDecomposed(benchmark::State& s) {
  load(s, objectLink("banana_decomposed", "ycb_011_banana", "{}"));
}
void BM_MugLinkHull(benchmark::State& s) {
  load(s, objectLink("mug_hull", "ycb_025_mug", "{\"decompose\": false}"));
}
void BM_MugLinkWrappedDecomposed(benchmark::State& s) {
  load(s, objectLink("mug_wrapped", "ycb_025_mug", "{}"));
}
BENCHMARK(BM_FrankaHull)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrankaDefault)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrankaForcedDecomposition)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BananaLinkHull)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BananaLinkDecomposed)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MugLinkHull)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MugLinkWrappedDecomposed)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
