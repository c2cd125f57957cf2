// holding_rate: what a user waits for, grasps that hold robustly per CPU-second of a validated
// default build (`taskmap build`, robust hold test), per hand x object of the reference set
// (bundled hands and objects) and the real set (--real DIR, default $TASKMAP_REAL_DIR or
// ../shared/real: the Franka and Allegro hands, the LEAP hand as MJCF; YCB banana and mug).
// Per pair, in one process, the previous implementation against the current one: the same
// build (seed, trials, one thread) with the hold test's pushes run their whole 2 s (the protocol
// as published, `--full`) and with settled pushes (the default; docs/VALIDATION.md). Prints per
// pair and build: trials, force-closure grasps tested in physics, grasps kept, CPU seconds (the
// build's own: sampling, simulation, quality, hold test), kept grasps per CPU-second, tested
// grasps per hold-test CPU-second, and the ratio of the two builds' rates; whether they kept
// the same grasps. A pair that keeps nothing in --trials says so.
//   holding_rate [--real DIR] [--valid N (5)] [--trials N (3000)] [--only A|B|...]
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_only.hpp"
#include "taskmap/builder/build_knobs.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

struct Pair {
  std::string hand_name, hand_path, object_name, object_path;
};

struct Run {
  std::uint64_t trials = 0, tested = 0, kept = 0;
  double cpu = 0.0, hold_cpu = 0.0;
  Eigen::MatrixXd poses;
};

Run build(const ObjectModel& object, const HandModel& hand, std::uint64_t valid,
          std::uint64_t trials, bool settle) {
  BuildKnobs k;  // taskmap build's defaults
  k.valid = valid;
  k.trials = trials;
  k.threads = 1;
  k.no_cluster = true;
  BuildOptions o = buildOptionsOf(k, KnobStyle::kCommandLine);
  o.hold_test_options.hold.settle_stop = settle;
  const BuildResult r = buildMap(object, hand, o);
  const BuildTiming& t = r.timing;
  Run run;
  run.trials = t.trials_simulated;
  run.tested = t.hold_tests;
  run.kept = r.map.grasps.size();
  run.hold_cpu = t.hold_test_seconds;
  run.cpu = t.sampling_seconds + t.simulation_seconds + t.quality_seconds + t.hold_test_seconds;
  run.poses = r.map.grasps.pose;
  return run;
}

std::vector<Pair> pairs(const std::string& src, const std::string& real) {
  std::vector<Pair> out;
  for (const std::string h : {"barrett", "humanoid", "panda"})
    for (const std::string o : {"box", "cylinder", "basket", "mug"})
      out.push_back({h, src + "/meshes/hands/" + h + "/" + h + ".urdf", o,
                     src + "/meshes/objects/" + o + ".obj"});
  if (!fs::exists(real)) {
    std::printf("real set not found at %s: reference set only\n", real.c_str());
    return out;
  }
  const std::vector<std::pair<std::string, std::string>> hands = {
      {"franka", real + "/hands/franka_hand/franka_hand.urdf"},
      {"allegro", real + "/hands/allegro_right/allegro_hand_description_right.urdf"},
      {"leap_mjcf", src + "/tests/data/real/hands/leap_hand_mjcf/right_hand.xml"}};
  for (const auto& [name, path] : hands)
    for (const std::string o : {"ycb_011_banana", "ycb_025_mug"})
      out.push_back({name, path, o, real + "/objects/" + o + ".obj"});
  return out;
}

double rate(std::uint64_t n, double seconds) {
  return seconds > 0.0 ? static_cast<double>(n) / seconds : 0.0;
}

void print(const Pair& p, const char* which, const Run& r) {
  std::printf("%-10s %-15s %-8s %7llu %7llu %5llu %9.2f %11.2f %13.1f%s\n", p.hand_name.c_str(),
              p.object_name.c_str(), which, static_cast<unsigned long long>(r.trials),
              static_cast<unsigned long long>(r.tested), static_cast<unsigned long long>(r.kept),
              r.cpu, rate(r.kept, r.cpu), rate(r.tested, r.hold_cpu),
              r.kept == 0 ? "  (nothing kept in the trial budget)" : "");
}

int benchMain(int argc, char** argv) {
  const char* env = std::getenv("TASKMAP_REAL_DIR");
  std::string real = env != nullptr ? env : std::string(TASKMAP_SOURCE_DIR) + "/../shared/real";
  std::uint64_t valid = 5, trials = 3000;
  std::string only;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i], v = argv[i + 1];
    if (a == "--real")
      real = v;
    else if (a == "--valid")
      valid = std::stoull(v);
    else if (a == "--trials")
      trials = std::stoull(v);
    else if (a == "--only")
      only = v;
    else
      throw Error("holding_rate: unknown option " + a + " (--real, --valid, --trials, --only)");
  }
  std::printf("robust default builds, one thread, --valid %llu --trials %llu --seed 1\n",
              static_cast<unsigned long long>(valid), static_cast<unsigned long long>(trials));
  std::printf("%-10s %-15s %-8s %7s %7s %5s %9s %11s %13s\n", "hand", "object", "pushes", "trials",
              "tested", "kept", "CPU s", "kept/CPU-s", "tested/hold-s");
  double sum_full = 0.0, sum_settled = 0.0;
  for (const Pair& p : pairs(TASKMAP_SOURCE_DIR, real)) {
    if (!testing::selectedByOnly(only, p.hand_name + " " + p.object_name) ||
        !fs::exists(p.object_path))
      continue;
    const HandModel hand = HandModel::load(p.hand_path);
    const ObjectModel object = ObjectModel::load(p.object_path, MeshLoadOptions{});
    const Run full = build(object, hand, valid, trials, false);
    const Run settled = build(object, hand, valid, trials, true);
    print(p, "full", full);
    print(p, "settled", settled);
    const double a = rate(full.kept, full.cpu), b = rate(settled.kept, settled.cpu);
    std::printf("%-10s %-15s settled/full: kept per CPU-second %.2fx, same grasps kept: %s\n",
                p.hand_name.c_str(), p.object_name.c_str(), a > 0.0 ? b / a : 0.0,
                full.poses == settled.poses ? "yes" : "no");
    sum_full += full.cpu;
    sum_settled += settled.cpu;
  }
  std::printf("all pairs: CPU seconds full %.1f, settled %.1f (%.2fx)\n", sum_full, sum_settled,
              sum_settled > 0.0 ? sum_full / sum_settled : 0.0);
  return 0;
}

}  // namespace
}  // namespace taskmap

int main(int argc, char** argv) {
  try {
    return taskmap::benchMain(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "holding_rate: %s\n", e.what());
    return 1;
  }
}
