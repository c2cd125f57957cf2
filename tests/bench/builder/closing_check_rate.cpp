// closing_check_rate: what the closing check (BuildOptions::closing_check, issue 28) costs a
// build, in one process against the default build of the same hand x object: stored grasps per
// CPU-second (stored / the workers' sampling + simulation + quality CPU seconds, as the build
// summary; the check's time is part of quality), their ratio to the default, the check's CPU per
// checked grasp, and the share of force-closure grasps it passes, for the modes closing and
// pushes with the default settings and pushes with ClosingCheckOptions::earlyVerdict()
// ("pushes-early": 8 ms steps, 0.1 s closing, pushes ending at rest). One thread, seed 1.
//
//   closing_check_rate [--valid N] [--trials N]
//                      [HAND OBJECT ...]   (default: barrett cylinder, humanoid box, panda box)
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "taskmap/builder/map_builder.hpp"

namespace taskmap {
namespace {

struct Run {
  double stored_per_cpu_s = 0.0, check_ms = 0.0, pass = 0.0;
  std::size_t stored = 0;
  std::uint64_t trials = 0;
};

Run runOnce(const ObjectModel& object, const HandModel& hand, BuildOptions o) {
  const BuildResult r = buildMap(object, hand, o);
  const BuildTiming& t = r.timing;
  Run out;
  const double cpu = t.sampling_seconds + t.simulation_seconds + t.quality_seconds;
  out.stored = r.map.grasps.size();
  out.trials = r.map.sampling.trials;
  out.stored_per_cpu_s = static_cast<double>(out.stored) / cpu;
  if (t.closing_checks > 0) {
    out.check_ms = 1e3 * t.closing_check_seconds / static_cast<double>(t.closing_checks);
    out.pass = static_cast<double>(out.stored) / static_cast<double>(t.closing_checks);
  }
  return out;
}

}  // namespace
}  // namespace taskmap

int main(int argc, char** argv) {
  using namespace taskmap;
  std::uint64_t valid = 20, trials = 20000;
  const std::string hands = TASKMAP_HANDS_DIR, objects = TASKMAP_OBJECTS_DIR;
  std::vector<std::string> pairs;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--valid" && a + 1 < argc)
      valid = std::strtoull(argv[++a], nullptr, 10);
    else if (arg == "--trials" && a + 1 < argc)
      trials = std::strtoull(argv[++a], nullptr, 10);
    else
      pairs.push_back(arg);
  }
  if (pairs.empty()) pairs = {"barrett", "cylinder", "humanoid", "box", "panda", "box"};
  std::printf(
      "hand,object,default stored/CPU-s,mode,stored,trials,stored/CPU-s,ratio,"
      "check ms/grasp,check passes\n");
  for (std::size_t p = 0; p + 1 < pairs.size(); p += 2) {
    const HandModel hand = HandModel::load(hands + "/" + pairs[p] + "/" + pairs[p] + ".urdf");
    const ObjectModel object = ObjectModel::load(objects + "/" + pairs[p + 1] + ".obj");
    BuildOptions o;
    o.threads = 1;
    o.valid_target = valid;
    o.max_trials = trials;
    const Run base = runOnce(object, hand, o);
    for (int variant = 0; variant < 3; ++variant) {
      o.closing_check = variant == 2 ? ClosingCheckOptions::earlyVerdict() : ClosingCheckOptions();
      o.closing_check.mode = variant == 0 ? ClosingCheckMode::kClosing : ClosingCheckMode::kPushes;
      const Run c = runOnce(object, hand, o);
      std::printf("%s,%s,%.1f,%s,%zu,%llu,%.2f,%.4f,%.2f,%.2f\n", pairs[p].c_str(),
                  pairs[p + 1].c_str(), base.stored_per_cpu_s,
                  variant == 2 ? "pushes-early" : toString(o.closing_check.mode), c.stored,
                  static_cast<unsigned long long>(c.trials), c.stored_per_cpu_s,
                  c.stored_per_cpu_s / base.stored_per_cpu_s, c.check_ms, c.pass);
      std::fflush(stdout);
    }
  }
  return 0;
}
