// holding_rate: what a user waits for, grasps that hold robustly per CPU-second of a validated
// default build (`taskmap build`, robust hold test), per hand x object of the reference set
// (bundled hands and objects) and the real set (--real DIR, default $TASKMAP_REAL_DIR or
// ../shared/real: the Franka and Allegro hands, the LEAP hand as MJCF; YCB banana and mug).
// Per pair, in one process, a baseline against a candidate: the same build (seed, trials, one
// thread) with two hold tests. --compare settle (default): pushes run their whole 2 s (the
// protocol as published, `validate --full`) against settled pushes (the default);
// --compare integrator: the default (MuJoCo's `implicit`) against `implicitfast`
// (docs/VALIDATION.md, "The integrator"). Prints per pair and build: trials, force-closure
// grasps tested in physics, grasps kept, CPU seconds (the build's own: sampling, simulation,
// quality, hold test), kept grasps per CPU-second, tested grasps per hold-test CPU-second, and
// the ratio of the two builds' rates; whether they kept the same grasps. A pair that keeps
// nothing in --trials says so.
//   holding_rate [--real DIR] [--valid N (5)] [--trials N (3000)] [--only A|B|...]
//                [--compare settle|integrator]
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

// The hold test's settings a build changes: today's default, or a baseline's.
struct HoldChoice {
  bool settle = true;
  HoldTestOptions::Integrator integrator = HoldTestOptions::Integrator::kImplicit;
};

/// The baseline and the candidate of a comparison, and their names.
struct Comparison {
  HoldChoice baseline, candidate;
  std::string baseline_name, candidate_name;
};

Comparison comparisonOf(const std::string& name) {
  using I = HoldTestOptions::Integrator;
  if (name == "settle") return {{false, I::kImplicit}, {true, I::kImplicit}, "full", "settled"};
  if (name == "integrator")
    return {{true, I::kImplicit}, {true, I::kImplicitFast}, "implicit", "fast"};
  throw Error("holding_rate: --compare must be settle or integrator, not " + name);
}

Run build(const ObjectModel& object, const HandModel& hand, std::uint64_t valid,
          std::uint64_t trials, const HoldChoice& choice) {
  BuildKnobs k;  // taskmap build's defaults
  k.valid = valid;
  k.trials = trials;
  k.threads = 1;
  k.no_cluster = true;
  BuildOptions o = buildOptionsOf(k, KnobStyle::kCommandLine);
  o.hold_test_options.hold.settle_stop = choice.settle;
  o.hold_test_options.hold.integrator = choice.integrator;
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
  std::printf("%-10s %-15s %-9s %7llu %7llu %5llu %9.2f %11.2f %13.1f%s\n", p.hand_name.c_str(),
              p.object_name.c_str(), which, static_cast<unsigned long long>(r.trials),
              static_cast<unsigned long long>(r.tested), static_cast<unsigned long long>(r.kept),
              r.cpu, rate(r.kept, r.cpu), rate(r.tested, r.hold_cpu),
              r.kept == 0 ? "  (nothing kept in the trial budget)" : "");
}

int benchMain(int argc, char** argv) {
  const char* env = std::getenv("TASKMAP_REAL_DIR");
  std::string real = env != nullptr ? env : std::string(TASKMAP_SOURCE_DIR) + "/../shared/real";
  std::uint64_t valid = 5, trials = 3000;
  std::string only, compare = "settle";
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
    else if (a == "--compare")
      compare = v;
    else
      throw Error("holding_rate: unknown option " + a +
                  " (--real, --valid, --trials, --only, --compare)");
  }
  const Comparison c = comparisonOf(compare);
  std::printf("robust default builds, one thread, --valid %llu --trials %llu --seed 1, %s vs %s\n",
              static_cast<unsigned long long>(valid), static_cast<unsigned long long>(trials),
              c.baseline_name.c_str(), c.candidate_name.c_str());
  std::printf("%-10s %-15s %-9s %7s %7s %5s %9s %11s %13s\n", "hand", "object", "hold test",
              "trials", "tested", "kept", "CPU s", "kept/CPU-s", "tested/hold-s");
  double sum_base = 0.0, sum_now = 0.0;
  for (const Pair& p : pairs(TASKMAP_SOURCE_DIR, real)) {
    if (!testing::selectedByOnly(only, p.hand_name + " " + p.object_name) ||
        !fs::exists(p.object_path))
      continue;
    const HandModel hand = HandModel::load(p.hand_path);
    const ObjectModel object = ObjectModel::load(p.object_path, MeshLoadOptions{});
    const Run before = build(object, hand, valid, trials, c.baseline);
    const Run now = build(object, hand, valid, trials, c.candidate);
    print(p, c.baseline_name.c_str(), before);
    print(p, c.candidate_name.c_str(), now);
    const double a = rate(before.kept, before.cpu), b = rate(now.kept, now.cpu);
    std::printf("%-10s %-15s %s/%s: kept per CPU-second %.2fx, same grasps kept: %s\n",
                p.hand_name.c_str(), p.object_name.c_str(), c.candidate_name.c_str(),
                c.baseline_name.c_str(), a > 0.0 ? b / a : 0.0,
                before.poses == now.poses ? "yes" : "no");
    sum_base += before.cpu;
    sum_now += now.cpu;
  }
  std::printf("all pairs: CPU seconds %s %.1f, %s %.1f (%.2fx)\n", c.baseline_name.c_str(),
              sum_base, c.candidate_name.c_str(), sum_now,
              sum_now > 0.0 ? sum_base / sum_now : 0.0);
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
