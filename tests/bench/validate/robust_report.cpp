// What the robust label's variants measure on a map's grasps (docs/history/validation-2026-11.md,
// "The robust label"): every variant of every grasp (RobustHoldOptions::all_variants), how often
// each fails where the nominal protocol holds, the margin's distribution, and two checks of the
// label: the protocol with the palm 0.5 mm back along the approach axis (the replay offset)
// and, with --compare-full, the settled-push stop against the full protocol (labels and steps);
// with --compare-defaults, the runs with the knobs below against the default options, grasp by
// grasp in the same process (labels, steps and CPU).
// The settled runs take the knobs below (the full protocol keeps the defaults): --implicitfast
// integrates them with DexGraspBench's integrator (docs/VALIDATION.md, "The integrator"). The
// "ceiling" line is what the protocol's step counts allow at the map's cost per step.
//
//   robust_report MAP.h5 [--hand URDF] [--grasps N] [--threads N] [--compare-full]
//                 [--compare-defaults] [--json OUT]
//                 [--nominal-only] [--joint-speed V] [--iterations N] [--tolerance T]
//                 [--noslip N] [--implicitfast] [--pieces N]
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/mapstore/recorded_hand.hpp"
#include "taskmap/validate/robust_hold.hpp"
#include "taskmap/validate/validate_map.hpp"

namespace {

using namespace taskmap;

double cpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Args {
  std::string map, hand, json;
  std::size_t grasps = 0;
  int threads = 2;
  bool compare_full = false;
  bool compare_defaults = false;  // --compare-defaults: the comparison runs the default options
  bool nominal_only = false;      // --nominal-only: the settled protocol alone (no variants)
  double joint_speed = 0.0;       // --joint-speed: settle_joint_speed (0: the default)
  int iterations = 0;      // --iterations: solver_iterations of the settled runs (0: default)
  double tolerance = 0.0;  // --tolerance: solver_tolerance of the settled runs (0: default)
  int noslip = -1;         // --noslip: noslip_iterations of the settled runs (-1: default)
  bool fast = false;       // --implicitfast: the settled runs integrate `implicitfast`
  int pieces = 0;          // --pieces: object_max_pieces of the settled runs (0: default)
};

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw Error(s + " needs a value");
      return argv[++i];
    };
    if (s == "--hand")
      a.hand = next();
    else if (s == "--grasps")
      a.grasps = std::stoul(next());
    else if (s == "--threads")
      a.threads = std::stoi(next());
    else if (s == "--json")
      a.json = next();
    else if (s == "--compare-full")
      a.compare_full = true;
    else if (s == "--compare-defaults")
      a.compare_defaults = true;
    else if (s == "--nominal-only")
      a.nominal_only = true;
    else if (s == "--joint-speed")
      a.joint_speed = std::stod(next());
    else if (s == "--iterations")
      a.iterations = std::stoi(next());
    else if (s == "--tolerance")
      a.tolerance = std::stod(next());
    else if (s == "--noslip")
      a.noslip = std::stoi(next());
    else if (s == "--implicitfast")
      a.fast = true;
    else if (s == "--pieces")
      a.pieces = std::stoi(next());
    else if (a.map.empty())
      a.map = s;
    else
      throw Error("unexpected argument '" + s + "'");
  }
  if (a.map.empty()) throw Error("usage: robust_report MAP.h5 [--hand URDF] [--grasps N] ...");
  if (a.compare_full && a.compare_defaults)
    throw Error("--compare-full and --compare-defaults exclude each other");
  return a;
}

struct GraspRow {
  RobustHoldResult robust;
  HoldResult back;             // protocol (settled stop), palm 0.5 mm back
  HoldResult full, full_back;  // the comparison: full protocol or default options
  double robust_cpu = 0.0, full_cpu = 0.0;
};

template <typename F>
void parallelFor(std::size_t n, int threads, F f) {
  std::atomic<std::size_t> next{0};
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&] {
      for (std::size_t i; (i = next.fetch_add(1)) < n;) f(i);
    });
  for (auto& th : pool) th.join();
}

double threadCpu() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// What the protocol's step counts allow at this map's cost per MuJoCo step (docs/PERFORMANCE.md,
// "What the protocol allows"): every grasp runs the closing (2 phases of interpolation_stages x
// steps_per_stage steps) before any push, and a robust grasp runs every variant, each at least as
// long as the shortest nominal run of a grasp that held.
void printCeiling(const std::vector<GraspRow>& rows, std::size_t variants,
                  const HoldTestOptions& o) {
  double cpu = 0.0;
  long long steps = 0;
  int fewest = 0;
  for (const GraspRow& r : rows) {
    cpu += r.robust_cpu;
    steps += r.robust.steps;
    if (r.robust.nominal.holds && (fewest == 0 || r.robust.nominal.steps < fewest))
      fewest = r.robust.nominal.steps;
  }
  if (steps == 0) return;
  const double per_step = cpu / static_cast<double>(steps);
  const int closing = 2 * o.interpolation_stages * o.steps_per_stage;
  std::printf(
      "ceiling: %.1f us CPU per MuJoCo step, %.1f grasps per CPU-second tested here; the closing "
      "alone (%d steps): at most %.1f grasps per CPU-second",
      1e6 * per_step, static_cast<double>(rows.size()) / cpu, closing, 1.0 / (per_step * closing));
  if (fewest > 0)
    std::printf(
        "; a grasp that held took at least %d steps, so a robust grasp (%zu variants) at least "
        "%lld: at most %.2f robust grasps per CPU-second if every grasp tested were robust",
        fewest, variants, static_cast<long long>(fewest) * static_cast<long long>(variants),
        1.0 / (per_step * static_cast<double>(fewest) * static_cast<double>(variants)));
  std::printf("\n");
}

int run(const Args& a) {
  const TaskMapData map = readMap(a.map);
  const HandModel hand = HandModel::load(a.hand.empty() ? findMapHandUrdf(map) : a.hand);
  const ObjectModel object = mapObjectModel(map);
  RobustHoldOptions ro;
  ro.all_variants = true;
  if (a.joint_speed > 0) ro.hold.settle_joint_speed = a.joint_speed;
  if (a.iterations > 0) ro.hold.solver_iterations = a.iterations;
  if (a.tolerance > 0) ro.hold.solver_tolerance = a.tolerance;
  if (a.noslip >= 0) ro.hold.noslip_iterations = a.noslip;
  if (a.fast) ro.hold.integrator = HoldTestOptions::Integrator::kImplicitFast;
  if (a.pieces > 0) ro.hold.object_max_pieces = a.pieces;
  const RobustHoldTester robust(hand, object, ro);
  HoldTestOptions full_o;  // the comparison: the full protocol, or the defaults
  full_o.settle_stop = a.compare_defaults;
  const HoldTester full(hand, object, full_o);
  const Eigen::Vector3d back = -0.0005 * hand.approachAxis();
  const std::size_t n = a.grasps ? std::min(a.grasps, map.grasps.size()) : map.grasps.size();
  const std::size_t variants_n = robust.variants().size();
  std::vector<GraspRow> rows(n);
  const double t0 = cpuSeconds();
  parallelFor(n, a.threads, [&](std::size_t i) {
    const Pose palm = map.grasps.poseAt(i);
    const Eigen::VectorXd q = map.grasps.joints.row(static_cast<Eigen::Index>(i)).transpose();
    Pose moved = palm;
    moved.position += palm.orientation * back;
    GraspRow& r = rows[i];
    double c = threadCpu();
    if (a.nominal_only) {
      r.robust.nominal = robust.nominal().test(palm, q);
      r.robust.steps = r.robust.nominal.steps;
      r.robust.variant_held.assign(variants_n, 255);
    } else {
      r.robust = robust.test(palm, q);
    }
    r.robust_cpu = threadCpu() - c;
    r.back = robust.nominal().test(moved, q);
    if (a.compare_full || a.compare_defaults) {
      c = threadCpu();
      r.full = full.test(palm, q);
      r.full_cpu = threadCpu() - c;
      r.full_back = full.test(moved, q);
    }
  });
  const double cpu = cpuSeconds() - t0;
  const auto& variants = robust.variants();
  // Per variant: failures where the nominal (with margin) held.
  std::vector<int> fails(variants.size(), 0), only(variants.size(), 0);
  int nominal = 0, robust_n = 0, margin_fail = 0, both = 0, robust_both = 0;
  for (const GraspRow& r : rows) {
    nominal += r.robust.nominal.holds;
    robust_n += r.robust.robust;
    margin_fail += r.robust.nominal.holds && r.robust.variant_held[0] == 0;
    both += r.robust.nominal.holds && r.back.holds;
    robust_both += r.robust.robust && r.robust.nominal.holds && r.back.holds;
    if (r.robust.variant_held[0] != 1) continue;
    int failed = 0, last = -1;
    for (std::size_t k = 1; k < variants.size(); ++k)
      if (r.robust.variant_held[k] == 0) ++failed, last = static_cast<int>(k), ++fails[k];
    if (failed == 1) ++only[static_cast<std::size_t>(last)];
  }
  const HoldModelInfo& info = robust.nominal().info();
  std::printf(
      "map %s: %zu grasps, hand %s, object pieces %d (volume %+.1f %%; second decomposition: "
      "%s)\n",
      a.map.c_str(), n, hand.name().c_str(), info.object_pieces, 100.0 * info.object_volume_error,
      variants.back().kind == HoldVariant::Kind::kDecomposition ? "yes" : "same pieces");
  std::printf("protocol holds %d (%.1f %%); within the margin %d; robust %d (%.1f %%)\n", nominal,
              100.0 * nominal / n, nominal - margin_fail, robust_n, 100.0 * robust_n / n);
  std::printf(
      "protocol at the pose and 0.5 mm back: %d of the %d that hold; of the robust: %d "
      "of %d (%.1f %%)\n",
      both, nominal, robust_both, robust_n, robust_n ? 100.0 * robust_both / robust_n : 0.0);
  std::printf("variant            fails where nominal held   the only failure\n");
  for (std::size_t k = 1; k < variants.size(); ++k)
    std::printf("  %-16s %8d %25d\n", variants[k].name().c_str(), fails[k], only[k]);
  std::printf(
      "CPU %.1f s for %zu grasps (robust, all variants, + the back test): %.2f grasps per "
      "CPU-second\n",
      cpu, n, n / cpu);
  printCeiling(rows, variants.size(), ro.hold);
  if (a.compare_full || a.compare_defaults) {
    int same = 0, settle_h_full_not = 0, full_h_settle_not = 0, same_back = 0;
    double cf = 0, cs = 0;
    long long steps_f = 0;
    for (const GraspRow& r : rows) {
      same += r.full.holds == r.robust.nominal.holds;
      settle_h_full_not += r.robust.nominal.holds && !r.full.holds;
      full_h_settle_not += !r.robust.nominal.holds && r.full.holds;
      same_back += r.full_back.holds == r.back.holds;
      steps_f += r.full.steps;
      cf += r.full_cpu;
      cs += r.robust_cpu;
    }
    const char* them = a.compare_full ? "full protocol" : "default options";
    const char* us = a.compare_full ? "settled stop" : "these knobs";
    std::printf(
        "%s vs %s (nominal label): %d of %zu equal; %s hold, %s not: %d; %s hold, %s not: "
        "%d; 0.5 mm back: %d equal\n",
        us, them, same, n, us, them, settle_h_full_not, them, us, full_h_settle_not, same_back);
    std::printf(
        "%s: %lld steps, %.2f CPU s (%.1f grasps per CPU-second); CPU %s / %s: %.2f (same "
        "process, grasp by grasp)\n",
        them, steps_f, cf, n / std::max(cf, 1e-9), them, us, cf / std::max(cs, 1e-9));
  }
  if (!a.json.empty()) {
    nlohmann::json j = nlohmann::json::array();
    for (std::size_t i = 0; i < n; ++i) {
      const GraspRow& r = rows[i];
      j.push_back({{"i", i},
                   {"nominal", r.robust.nominal.holds},
                   {"status", holdStatusName(r.robust.nominal.status)},
                   {"robust", r.robust.robust},
                   {"variants", r.robust.variant_held},
                   {"push_t", r.robust.push_translation},
                   {"push_r", r.robust.push_rotation},
                   {"nominal_push_t", r.robust.nominal.push_translation},
                   {"nominal_push_r", r.robust.nominal.push_rotation},
                   {"back", r.back.holds},
                   {"steps", r.robust.steps},
                   {"cpu", r.robust_cpu},
                   {"full", r.full.holds},
                   {"full_back", r.full_back.holds},
                   {"full_steps", r.full.steps},
                   {"full_cpu", r.full_cpu},
                   {"nominal_steps", r.robust.nominal.steps}});
    }
    nlohmann::json names = nlohmann::json::array();
    for (const auto& v : variants) names.push_back(v.name());
    std::ofstream(a.json)
        << nlohmann::json{{"map", a.map}, {"variants", names}, {"grasps", j}}.dump() << "\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::cerr << "robust_report: " << e.what() << "\n";
    return 1;
  }
}
