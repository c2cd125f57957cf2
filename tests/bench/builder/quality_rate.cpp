// quality_rate: the quality stage's cost in a build, the previous quality against today's
// default, in one process on the same trials, for every hand x object of the reference set
// (panda, barrett, humanoid, the Robotiq 2F-85 style test hand x cylinder, box, basket) and of
// the real set (--real DIR, default $TASKMAP_REAL_DIR: Franka hand, Allegro x YCB banana, YCB
// mug, ACRONYM mug). One thread (BuildOptions::threads = 1), seed 1, --valid force-closure
// grasps per build. Prints per pair:
//  - stored grasps per CPU-second (stored grasps / the workers' sampling + simulation + quality
//    CPU seconds, as the build summary) and quality CPU per scored grasp (BuildTiming::
//    quality_seconds / grasps_scored), "old" = QualityOptions volume kForceClosure (the builds
//    before issue 33: the whole 6-D hull of every stored grasp) and "new" = the build's default
//    (buildQualityDefaults: force closure and epsilon only), their ratios, and whether the two
//    maps hold the same grasps (poses, epsilons bit for bit);
//  - on the ok grasps of a --keep-invalid build, the per-link contact reduction
//    (QualityOptions::contacts_per_link = 2 and 3) against every contact: the share of grasps
//    whose force-closure verdict changes and the epsilon ratio (reduced / full; 5th, 50th, 95th
//    percentile over grasps force closure in both), and the NNLS closure pre-test's cost
//    (closure_pretest) against none on the same contact sets.
//   quality_rate [--real DIR] [--valid N] [--only SUBSTRING]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "taskmap/builder/map_builder.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/grasp_contacts.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

struct Item {
  std::string name, path;
  double scale = 1.0;
};

double threadSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Rate {
  double stored_per_cpu_s = 0.0, quality_us = 0.0, quality_share = 0.0;
};

Rate rateOf(const BuildResult& r) {
  const BuildTiming& t = r.timing;
  const double cpu = t.sampling_seconds + t.simulation_seconds + t.quality_seconds;
  Rate out;
  out.stored_per_cpu_s = static_cast<double>(r.map.grasps.size()) / cpu;
  out.quality_us =
      1e6 * t.quality_seconds / static_cast<double>(std::max<std::uint64_t>(t.grasps_scored, 1));
  out.quality_share = t.quality_seconds / cpu;
  return out;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

/// Reduction and pre-test on the ok grasps of a keep-invalid build.
void reductionReport(const ObjectModel& object, const HandModel& hand, BuildOptions o) {
  o.stored = StoredGrasps::kAllCompleted;
  o.cluster = false;
  const BuildResult all = buildMap(object, hand, o);
  const auto& mp = object.massProperties();
  const std::size_t n = all.map.grasps.size();
  std::vector<std::vector<Contact>> sets;
  for (std::size_t i = 0; i < n; ++i) sets.push_back(graspContacts(all.map.grasps, i));
  QualityOptions full;
  full.volume = VolumeMode::kNever;
  std::vector<QualityResult> ref;
  for (const auto& c : sets)
    ref.push_back(evaluateGrasp(c, mp.center_of_mass, mp.torque_scale, full));
  std::printf("    reduction on %zu ok grasps:", n);
  for (int k : {3, 2}) {
    QualityOptions q = full;
    q.contacts_per_link = k;
    int flips = 0;
    std::vector<double> ratio;
    for (std::size_t i = 0; i < n; ++i) {
      const QualityResult r = evaluateGrasp(sets[i], mp.center_of_mass, mp.torque_scale, q);
      flips += r.force_closure != ref[i].force_closure;
      if (r.force_closure && ref[i].force_closure) ratio.push_back(r.epsilon / ref[i].epsilon);
    }
    std::printf(" K=%d flips %.1f%%, eps ratio %.2f/%.2f/%.2f;", k,
                100.0 * flips / static_cast<double>(std::max<std::size_t>(n, 1)),
                percentile(ratio, 0.05), percentile(ratio, 0.5), percentile(ratio, 0.95));
  }
  QualityOptions pre = full;
  pre.closure_pretest = true;
  double t_plain = 0.0, t_pre = 0.0;
  for (int rep = 0; rep < 2; ++rep) {
    for (const QualityOptions* q : {&full, &pre}) {
      const double t0 = threadSeconds();
      for (const auto& c : sets) (void)evaluateGrasp(c, mp.center_of_mass, mp.torque_scale, *q);
      (q == &full ? t_plain : t_pre) += threadSeconds() - t0;
    }
  }
  std::printf(" pre-test %.0f vs %.0f us/grasp (%.2fx)\n",
              1e6 * t_pre / static_cast<double>(2 * std::max<std::size_t>(n, 1)),
              1e6 * t_plain / static_cast<double>(2 * std::max<std::size_t>(n, 1)),
              t_pre / std::max(t_plain, 1e-12));
}

void benchPair(const Item& h, const Item& o, std::uint64_t valid) {
  MeshLoadOptions lo;
  lo.scale = o.scale;
  const ObjectModel object = ObjectModel::load(o.path, lo);
  const HandModel hand = HandModel::load(h.path);
  BuildOptions now;
  now.threads = 1;
  now.valid_target = valid;
  now.cluster = false;
  BuildOptions before = now;
  before.quality.volume = VolumeMode::kForceClosure;
  const BuildResult a = buildMap(object, hand, before);  // the previous quality
  const BuildResult b = buildMap(object, hand, now);     // today's default
  const Rate ra = rateOf(a), rb = rateOf(b);
  const bool same = a.map.grasps.pose == b.map.grasps.pose &&
                    a.map.grasps.epsilon == b.map.grasps.epsilon &&
                    a.map.sampling.trials == b.map.sampling.trials;
  std::printf("%-13s %-12s %6zu %8.1f %8.1f %6.2fx %9.0f %9.0f %7.1fx %5.0f%% %5.0f%% %s\n",
              h.name.c_str(), o.name.c_str(), b.map.grasps.size(), ra.stored_per_cpu_s,
              rb.stored_per_cpu_s, rb.stored_per_cpu_s / ra.stored_per_cpu_s, ra.quality_us,
              rb.quality_us, ra.quality_us / std::max(rb.quality_us, 1e-9),
              100.0 * ra.quality_share, 100.0 * rb.quality_share, same ? "yes" : "NO");
  reductionReport(object, hand, now);
  std::fflush(stdout);
}

int mainImpl(int argc, char** argv) {
  std::string real = std::getenv("TASKMAP_REAL_DIR") ? std::getenv("TASKMAP_REAL_DIR") : "";
  std::uint64_t valid = 100;
  std::string only;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--real")
      real = argv[i + 1];
    else if (a == "--valid")
      valid = std::stoull(argv[i + 1]);
    else if (a == "--only")
      only = argv[i + 1];
    else
      throw Error("usage: quality_rate [--real DIR] [--valid N] [--only SUBSTRING]");
  }
  const std::string hands = TASKMAP_HANDS_DIR, objects = TASKMAP_OBJECTS_DIR;
  std::vector<Item> hs, os;
  for (const char* n : {"panda", "barrett", "humanoid"})
    hs.push_back({n, hands + "/" + n + "/" + n + ".urdf"});
  hs.push_back({"robotiq_style",
                std::string(TEST_DATA_DIR) + "/hands/robotiq_2f85_style/robotiq_2f85_style.urdf"});
  for (const char* n : {"cylinder", "box", "basket"}) os.push_back({n, objects + "/" + n + ".obj"});
  std::vector<std::pair<Item, Item>> pairs;
  for (const auto& h : hs)
    for (const auto& ob : os) pairs.push_back({h, ob});
  if (!real.empty() && fs::is_directory(real)) {
    const std::vector<Item> rh = {
        {"franka", real + "/hands/franka_hand/franka_hand.urdf"},
        {"allegro", real + "/hands/allegro_right/allegro_hand_description_right.urdf"}};
    const std::vector<Item> ro = {
        {"ycb_banana", real + "/objects/ycb_011_banana.obj"},
        {"ycb_mug", real + "/objects/ycb_025_mug.obj"},
        {"acronym_mug", real + "/objects/acronym_mug_10f6e09036350e92b3f21f1137c3c347.obj",
         0.0002682457830986903}};
    for (const auto& h : rh)
      for (const auto& ob : ro) pairs.push_back({h, ob});
  } else {
    std::printf("(no real set: pass --real DIR or set TASKMAP_REAL_DIR)\n");
  }
  std::printf(
      "one thread, seed 1, %llu force-closure grasps per build; old = volume of every "
      "stored grasp, new = the default (force closure and epsilon only)\n",
      static_cast<unsigned long long>(valid));
  std::printf("%-13s %-12s %6s %8s %8s %7s %9s %9s %8s %6s %6s %s\n", "hand", "object", "stored",
              "old g/s", "new g/s", "ratio", "old us/q", "new us/q", "ratio", "old q", "new q",
              "same");
  for (const auto& [h, ob] : pairs) {
    if (!only.empty() && (h.name + "/" + ob.name).find(only) == std::string::npos) continue;
    try {
      benchPair(h, ob, valid);
    } catch (const std::exception& e) {
      std::printf("%-13s %-12s skipped: %s\n", h.name.c_str(), ob.name.c_str(), e.what());
    }
  }
  return 0;
}

}  // namespace
}  // namespace taskmap

int main(int argc, char** argv) {
  try {
    return taskmap::mainImpl(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "quality_rate: %s\n", e.what());
    return 2;
  }
}
