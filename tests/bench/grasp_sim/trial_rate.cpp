// Grasp trials per second per core, culled and lean collision queries (the default) against the
// baseline (GraspSimDiagnostics::culled_queries = false: Bullet's BVH, GJK on every triangle in
// each link shape's bounding box, every exact hit computed), side by side in one process on the
// same trials, for every hand x object of the reference set (bundled hands, the Robotiq 2F-85 style
// test hand, bundled objects) and of the real set (--real DIR, default
// $TASKMAP_REAL_DIR: hands/franka_hand, hands/allegro_right, objects/*.obj; see the README of
// that folder; --extra DIR adds the real Robotiq 2F-85 and the YCB cracker box, soup can,
// mustard bottle and scissors of issue 33's extra inputs). Trials are drawn by the build's sampler
// (mixed, seed 1), one thread. Prints per pair: trials/s new and baseline, their ratio,
// force-closure ("valid") grasps per second of simulation, and on the trials both ran how many
// ended the same (status, palm pose, joints: bit for bit) and how many also have the same contacts
// bit for bit (box and hull contacts on fine meshes come from separating axes, not EPA: equal up to
// rounding, different at tied features, a face flat on a triangle, and where Bullet's GJK calls an
// overlapping pair apart; GraspSimDiagnostics::separating_axis_contacts).
//   grasp_sim_rate [--real DIR] [--extra DIR] [--seconds S] [--only SUBSTRING]
//                  [--baseline-seconds S] [--profile 1] [--versus bullet|axes]
// (--baseline-seconds 0 runs one baseline trial per pair: for profiling the new path; --profile 1
// adds per pair the new path's share of time per phase, queries per trial, the outcomes and the
// CPU time of the quality stage on the ok trials relative to the simulation's; --versus axes
// takes as baseline the default path without the closing's self-collision separating axes,
// GraspSimDiagnostics::self_collision_axes false).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "taskmap/core/error.hpp"
#include "taskmap/grasp_sim/grasp_simulator.hpp"
#include "taskmap/meshes/object_model.hpp"
#include "taskmap/quality/grasp_quality.hpp"
#include "taskmap/sampler/sampler.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// CPU seconds of the calling thread (trials/s per core, whatever else runs on the machine).
double threadSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

struct Item {
  std::string name, path;
  double scale = 1.0;
};

/// Reads an OBJ's triangles (polygons fanned), merging equal positions, and drops both faces of
/// every pair of identical faces with opposite orientation (zero-volume fins of scanned meshes,
/// which the loader refuses as border edges).
TriangleMesh readObjWithoutFins(const std::string& path, double scale) {
  std::ifstream in(path);
  if (!in) throw Error("cannot read " + path);
  TriangleMesh m;
  std::vector<int> remap;
  std::map<std::tuple<double, double, double>, int> ids;
  std::string line;
  std::vector<Eigen::Vector3i> faces;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      double x = 0, y = 0, z = 0;
      ls >> x >> y >> z;
      const auto key = std::make_tuple(x, y, z);
      auto it = ids.find(key);
      if (it == ids.end()) {
        it = ids.emplace(key, static_cast<int>(m.vertices.size())).first;
        m.vertices.emplace_back(scale * x, scale * y, scale * z);
      }
      remap.push_back(it->second);
    } else if (tag == "f") {
      std::vector<int> poly;
      std::string tok;
      while (ls >> tok) poly.push_back(remap.at(static_cast<std::size_t>(std::stoi(tok) - 1)));
      for (std::size_t k = 2; k < poly.size(); ++k)
        faces.emplace_back(poly[0], poly[k - 1], poly[k]);
    }
  }
  std::map<std::array<int, 3>, int> count;
  auto key = [](const Eigen::Vector3i& f) {
    std::array<int, 3> k = {f[0], f[1], f[2]};
    std::sort(k.begin(), k.end());
    return k;
  };
  for (const auto& f : faces) ++count[key(f)];
  for (const auto& f : faces)
    if (count[key(f)] == 1) m.faces.push_back(f);
  return m;
}

ObjectModel loadObject(const Item& o) {
  MeshLoadOptions lo;
  lo.scale = o.scale;
  try {
    return ObjectModel::load(o.path, lo);
  } catch (const Error&) {
    return ObjectModel::fromMesh(readObjWithoutFins(o.path, o.scale), o.name, lo);
  }
}

struct Rate {
  double trials_per_s = 0.0;
  double valid_per_s = 0.0;
  double quality_over_sim = 0.0;  // CPU time of the quality stage / of the simulation
  std::vector<GraspResult> results;
};

/// Initial poses of trials 0, 1, ... drawn on demand (seed 1), shared by both modes.
struct Poses {
  const Sampler& sampler;
  std::vector<Pose> drawn;
  const Pose& at(std::size_t i) {
    while (drawn.size() <= i) drawn.push_back(sampler.sample(1, drawn.size()));
    return drawn[i];
  }
};

/// Runs trials 0, 1, ... until `seconds` have passed (at least `min_trials`; exactly
/// `exact_trials` when > 0). As a build does (BuildOptions::block_size), trials run in blocks
/// of `block_size`: a block is simulated, then its ok grasps are scored (with `quality`); only
/// the simulation is timed for trials/s.
Rate run(const GraspSimulator& sim, const ObjectModel& object, Poses& poses, double seconds,
         std::size_t min_trials, bool quality, std::size_t exact_trials, std::size_t block_size) {
  Rate r;
  double sim_s = 0.0, quality_s = 0.0;
  int valid = 0;
  const auto t_end = Clock::now() + std::chrono::duration<double>(seconds);
  // No time given (--baseline-seconds 0): just the minimum, in one block.
  const std::size_t block = seconds > 0.0 || exact_trials > 0 ? block_size : min_trials;
  for (std::size_t i = 0; i < 1000000; i += block) {
    if (exact_trials > 0 ? i >= exact_trials : (i >= min_trials && Clock::now() > t_end)) break;
    const std::size_t n = exact_trials > 0 ? std::min(block, exact_trials - i) : block;
    const double t0 = threadSeconds();
    for (std::size_t k = 0; k < n; ++k) r.results.push_back(sim.simulate(poses.at(i + k)));
    const double t1 = threadSeconds();
    sim_s += t1 - t0;
    for (std::size_t k = 0; k < n && quality; ++k) {
      const GraspResult& g = r.results[i + k];
      if (g.status == GraspStatus::kOk &&
          evaluateGrasp(g.contacts, object.massProperties().center_of_mass,
                        object.massProperties().torque_scale)
              .force_closure)
        ++valid;
    }
    quality_s += threadSeconds() - t1;
  }
  r.trials_per_s = static_cast<double>(r.results.size()) / sim_s;
  r.valid_per_s = valid / sim_s;
  r.quality_over_sim = quality_s / sim_s;
  return r;
}

/// The new path's phases (GraspSimDiagnostics::profile), queries per trial, outcome counts and the
/// quality stage's CPU time relative to the simulation's.
void printProfile(const std::vector<GraspResult>& results, double quality_over_sim) {
  double retract = 0.0, close = 0.0, contacts = 0.0, queries = 0.0;
  std::map<std::string, int> outcomes;
  for (const auto& g : results) {
    retract += g.stats.retract_seconds;
    close += g.stats.close_seconds;
    contacts += g.stats.contacts_seconds;
    queries += g.stats.queries;
    ++outcomes[toString(g.status)];
  }
  const double all = std::max(retract + close + contacts, 1e-12);
  const auto n = static_cast<double>(std::max<std::size_t>(results.size(), 1));
  std::printf(
      "    phases: retract %.0f%%, close+squeeze %.0f%%, contacts %.0f%%; %.1f queries/trial;",
      100.0 * retract / all, 100.0 * close / all, 100.0 * contacts / all, queries / n);
  for (const auto& [name, count] : outcomes) std::printf(" %s %d", name.c_str(), count);
  std::printf("; quality stage %.2fx the simulation time\n", quality_over_sim);
}

/// The same simulated grasp: status, palm pose, joints.
bool sameGrasp(const GraspResult& a, const GraspResult& b) {
  return a.status == b.status && a.pose.position == b.pose.position &&
         a.pose.orientation.coeffs() == b.pose.orientation.coeffs() && a.joints == b.joints;
}

/// sameGrasp and the same contacts bit for bit (and so the same fingers and palm in contact).
bool same(const GraspResult& a, const GraspResult& b) {
  if (!sameGrasp(a, b) || a.contacts.size() != b.contacts.size()) return false;
  if (a.fingers_in_contact != b.fingers_in_contact || a.palm_contact != b.palm_contact)
    return false;
  for (std::size_t i = 0; i < a.contacts.size(); ++i)
    if (!(a.contacts[i].point == b.contacts[i].point) || a.contacts[i].depth != b.contacts[i].depth)
      return false;
  return true;
}

/// FNV-1a over the bytes of every trial's status, pose, joints and contacts: equal digests mean
/// bit-identical results (to compare two builds on the same trials, --trials N).
unsigned long long digest(const std::vector<GraspResult>& results) {
  unsigned long long hsh = 1469598103934665603ULL;
  auto mix = [&](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) hsh = (hsh ^ b[i]) * 1099511628211ULL;
  };
  auto mixd = [&](double x) { mix(&x, sizeof x); };
  for (const auto& g : results) {
    const int st = static_cast<int>(g.status);
    mix(&st, sizeof st);
    for (int k = 0; k < 3; ++k) mixd(g.pose.position[k]);
    for (int k = 0; k < 4; ++k) mixd(g.pose.orientation.coeffs()[k]);
    for (Eigen::Index k = 0; k < g.joints.size(); ++k) mixd(g.joints[k]);
    for (const auto& c : g.contacts) {
      for (int k = 0; k < 3; ++k) mixd(c.point[k]);
      for (int k = 0; k < 3; ++k) mixd(c.normal[k]);
      mixd(c.depth);
      mix(&c.link, sizeof c.link);
    }
  }
  return hsh;
}

/// What a run of the bench measures (command line).
struct BenchOptions {
  double seconds = 2.0;            ///< per mode and pair
  double baseline_seconds = -1.0;  ///< the baseline's; < 0: `seconds`
  bool profile = false;            ///< phase shares of the new path
  bool quality = true;             ///< score the ok grasps (valid/s); off: simulation only
  std::size_t trials = 0;          ///< > 0: exactly this many trials per mode (not `seconds`)
  std::size_t block = 64;          ///< trials simulated before their grasps are scored (as a build)
  bool digest = false;             ///< print a digest of the new path's results
  /// The baseline: "bullet" (culled_queries false) or "axes" (the default path without the
  /// self-collision test's separating axes, GraspSimDiagnostics::self_collision_axes false).
  std::string versus = "bullet";
};

void benchPair(const Item& h, const Item& o, const BenchOptions& bo) {
  const double seconds = bo.seconds;
  const double baseline_seconds = bo.baseline_seconds < 0.0 ? seconds : bo.baseline_seconds;
  const bool profile = bo.profile;
  const ObjectModel object = loadObject(o);
  const HandModel hand = HandModel::load(h.path);
  SamplerOptions so;
  so.approach_axis = hand.approachAxis();
  const Sampler sampler(object, so);
  Poses poses{sampler, {}};
  GraspSimDiagnostics fast, base;
  if (bo.versus == "axes")
    base.self_collision_axes = false;
  else
    base.culled_queries = false;
  fast.profile = profile;
  const GraspSimulator sim_new(object, hand, {}, fast), sim_old(object, hand, {}, base);
  const Rate rn = run(sim_new, object, poses, seconds, 32, bo.quality, bo.trials, bo.block);
  const Rate ro = run(sim_old, object, poses, baseline_seconds, baseline_seconds > 0 ? 4 : 1,
                      bo.quality, baseline_seconds > 0 ? bo.trials : 0, bo.block);
  std::size_t n = std::min(rn.results.size(), ro.results.size()), agree = 0, exact = 0, ok = 0;
  for (std::size_t i = 0; i < n; ++i) {
    agree += sameGrasp(rn.results[i], ro.results[i]);
    exact += same(rn.results[i], ro.results[i]);
    ok += rn.results[i].status == GraspStatus::kOk;
  }
  std::printf("%-10s %-16s %6zu %10.1f %10.1f %7.1fx %9.1f %6.1f%% %5zu/%-5zu %5zu\n",
              h.name.c_str(), o.name.c_str(), object.mesh().faces.size(), rn.trials_per_s,
              ro.trials_per_s, rn.trials_per_s / ro.trials_per_s, rn.valid_per_s,
              100.0 * static_cast<double>(ok) / static_cast<double>(std::max<std::size_t>(n, 1)),
              agree, n, exact);
  if (profile) printProfile(rn.results, rn.quality_over_sim);
  if (bo.digest)
    std::printf("    digest of %zu trials: %016llx\n", rn.results.size(), digest(rn.results));
  std::fflush(stdout);
}

int mainImpl(int argc, char** argv) {
  std::string real = std::getenv("TASKMAP_REAL_DIR") ? std::getenv("TASKMAP_REAL_DIR") : "";
  BenchOptions bo;
  std::string only, extra;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--real")
      real = argv[i + 1];
    else if (a == "--extra")
      extra = argv[i + 1];
    else if (a == "--seconds")
      bo.seconds = std::stod(argv[i + 1]);
    else if (a == "--only")
      only = argv[i + 1];
    else if (a == "--baseline-seconds")
      bo.baseline_seconds = std::stod(argv[i + 1]);
    else if (a == "--profile")
      bo.profile = std::string(argv[i + 1]) == "1";
    else if (a == "--quality")
      bo.quality = std::string(argv[i + 1]) != "0";
    else if (a == "--trials")
      bo.trials = static_cast<std::size_t>(std::stoul(argv[i + 1]));
    else if (a == "--block")
      bo.block = std::max<std::size_t>(1, std::stoul(argv[i + 1]));
    else if (a == "--digest")
      bo.digest = std::string(argv[i + 1]) == "1";
    else if (a == "--versus" &&
             (std::string(argv[i + 1]) == "bullet" || std::string(argv[i + 1]) == "axes"))
      bo.versus = argv[i + 1];
    else
      throw Error(
          "usage: grasp_sim_rate [--real DIR] [--extra DIR] [--seconds S] [--only SUBSTRING] "
          "[--baseline-seconds S] [--profile 1] [--quality 0] [--trials N] [--digest 1] [--block "
          "N] [--versus bullet|axes]");
  }
  const std::string hands = TASKMAP_HANDS_DIR, objects = TASKMAP_OBJECTS_DIR;
  std::vector<Item> hs, os;
  for (const char* n : {"panda", "barrett", "humanoid"})
    hs.push_back({n, hands + "/" + n + "/" + n + ".urdf"});
  // A Robotiq 2F-85 style test hand (10 mesh links, four-bar jaws) stands in for the real one.
  hs.push_back({"robotiq_style",
                std::string(TEST_DATA_DIR) + "/hands/robotiq_2f85_style/robotiq_2f85_style.urdf"});
  for (const char* n : {"cylinder", "basket", "mug"}) os.push_back({n, objects + "/" + n + ".obj"});
  if (!real.empty() && fs::is_directory(real)) {
    hs.push_back({"franka", real + "/hands/franka_hand/franka_hand.urdf"});
    hs.push_back({"allegro", real + "/hands/allegro_right/allegro_hand_description_right.urdf"});
    os.push_back({"ycb_banana", real + "/objects/ycb_011_banana.obj"});
    os.push_back({"ycb_mug", real + "/objects/ycb_025_mug.obj"});
    os.push_back({"acronym_mug", real + "/objects/acronym_mug_10f6e09036350e92b3f21f1137c3c347.obj",
                  0.0002682457830986903});
  } else {
    std::printf("(no real set: pass --real DIR or set TASKMAP_REAL_DIR)\n");
  }
  if (!extra.empty() && fs::is_directory(extra)) {  // issue 33's extra real inputs (not committed)
    hs.push_back({"robotiq", extra + "/hands/robotiq_2f85/robotiq_arg2f_85.urdf"});
    for (const char* n : {"ycb_003_cracker_box", "ycb_005_tomato_soup_can",
                          "ycb_006_mustard_bottle", "ycb_037_scissors"})
      os.push_back({std::string(n).substr(8), extra + "/objects/" + n + ".obj"});
  }
  std::printf("one thread; trials drawn by the mixed sampler, seed 1; %.1f s per mode and pair%s\n",
              bo.seconds, bo.quality ? "" : "; quality not scored (valid/s 0)");
  std::printf("%-10s %-16s %6s %10s %10s %8s %9s %7s %11s %5s\n", "hand", "object", "faces",
              "new/s", "base/s", "ratio", "valid/s", "ok", "same", "bits");
  for (const auto& h : hs)
    for (const auto& o : os) {
      if (!only.empty() && (h.name + "/" + o.name).find(only) == std::string::npos) continue;
      try {
        benchPair(h, o, bo);
      } catch (const std::exception& e) {
        std::printf("%-10s %-16s skipped: %s\n", h.name.c_str(), o.name.c_str(), e.what());
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
    std::fprintf(stderr, "grasp_sim_rate: %s\n", e.what());
    return 2;
  }
}
