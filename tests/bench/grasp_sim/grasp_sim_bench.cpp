// Grasp trials per second per core for each reference hand on the reference cylinder and
// basket, with the share of time spent retracting, closing (incl. squeeze) and extracting
// contacts. Poses as the volume sampler draws them: a uniform point inside the object
// (ObjectModel::sampleInside) and a uniform orientation (Rng::rotation).
// Baseline: Dex-Net's published 16-22 ms per grasp evaluation, about 50 trials/s per core
// (counter x_dexnet = trials/s / 50). The finger_first variants allow the fingers to touch
// before the palm (GraspSimOptions::require_palm_contact = false).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "taskmap/core/random.hpp"
#include "taskmap/grasp_sim/grasp_simulator.hpp"
#include "test_meshes.hpp"

namespace taskmap {
namespace {

constexpr double kDexNetTrialsPerSecond = 50.0;
constexpr int kPoses = 512;

struct Setup {
  std::unique_ptr<GraspSimulator> sim;
  std::vector<Pose> poses;
  std::string error;
};

Setup& setup(const std::string& hand_name, const std::string& object_name, bool finger_first) {
  static std::map<std::string, Setup> cache;
  const std::string key = hand_name + "/" + object_name + (finger_first ? "/ff" : "");
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  Setup& s = cache[key];
  const std::string obj_path = std::string(TASKMAP_OBJECTS_DIR) + "/" + object_name + ".obj";
  if (!std::filesystem::exists(obj_path)) {
    s.error = "missing " + obj_path;
    return s;
  }
  try {
    const ObjectModel object = ObjectModel::load(obj_path);
    const HandModel hand = HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/" + hand_name + "/" +
                                           hand_name + ".urdf");
    GraspSimOptions o;
    o.require_palm_contact = !finger_first;
    GraspSimDiagnostics d;
    d.profile = true;
    s.sim = std::make_unique<GraspSimulator>(object, hand, o, d);
    for (int i = 0; i < kPoses; ++i) {
      Rng rng(7, static_cast<std::uint64_t>(i));
      Pose p;
      p.position = object.sampleInside(rng);
      p.orientation = rng.rotation();
      s.poses.push_back(p);
    }
  } catch (const std::exception& e) {
    s.error = e.what();
  }
  return s;
}

void BM_GraspTrial(benchmark::State& state, const std::string& hand, const std::string& object,
                   bool finger_first) {
  Setup& s = setup(hand, object, finger_first);
  if (!s.sim) {
    state.SkipWithError(s.error.c_str());
    return;
  }
  std::size_t i = 0;
  double retract = 0, close = 0, contacts = 0, ok = 0, queries = 0, n = 0;
  std::map<GraspStatus, double> count;
  for (auto _ : state) {
    const GraspResult r = s.sim->simulate(s.poses[i]);
    benchmark::DoNotOptimize(r.contacts.data());
    retract += r.stats.retract_seconds;
    close += r.stats.close_seconds;
    contacts += r.stats.contacts_seconds;
    queries += r.stats.queries;
    ok += r.status == GraspStatus::kOk;
    count[r.status] += 1;
    n += 1;
    i = (i + 1) % s.poses.size();
  }
  const double total = retract + close + contacts;
  state.counters["trials_per_s"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
  state.counters["x_dexnet"] =
      benchmark::Counter(n / kDexNetTrialsPerSecond, benchmark::Counter::kIsRate);
  state.counters["ok_frac"] = ok / n;
  for (GraspStatus st : allGraspStatuses())
    if (st != GraspStatus::kOk && count[st] > 0) state.counters[toString(st)] = count[st] / n;
  state.counters["queries"] = queries / n;
  state.counters["retract%"] = 100 * retract / total;
  state.counters["close%"] = 100 * close / total;
  state.counters["contacts%"] = 100 * contacts / total;
}

void registerAll() {
  for (bool finger_first : {false, true})
    for (const char* hand : {"panda", "barrett", "humanoid"})
      for (const char* object : {"cylinder", "basket"})
        benchmark::RegisterBenchmark((std::string("GraspTrial/") + hand + "/" + object +
                                      (finger_first ? "/finger_first" : ""))
                                         .c_str(),
                                     [hand, object, finger_first](benchmark::State& st) {
                                       BM_GraspTrial(st, hand, object, finger_first);
                                     })
            ->Unit(benchmark::kMicrosecond)
            ->MinTime(1.0);
}

}  // namespace
}  // namespace taskmap

int main(int argc, char** argv) {
  taskmap::registerAll();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
