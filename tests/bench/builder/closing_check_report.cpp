// closing_check_report: how well the closing check (closing with the object free,
// grasp_sim/closing_check.hpp) predicts the physics hold test. For maps labelled by `taskmap
// validate`, runs one or more variants of the check (different ClosingCheckOptions) on every
// labelled grasp, interleaved grasp by grasp in one process, and prints one CSV row per grasp
// and variant (row, map, variant, grasp, hold label, validator status, translation, rotation,
// initial penetration, verdict, validator translation, epsilon, failed push, steps, settle
// steps, closing steps, check CPU ms, then the steps of each push -x .. +z), then per map and
// variant the confusion matrix and the check's cost per grasp against the quality stage's
// (evaluateGrasp) on the same grasps, and at the end per hand and variant precision, recall and ms
// per grasp. Not a unit test.
//
//   closing_check_report [--mode closing|pushes] [--grasps N] [--variant NAME:KEY=V,KEY=V ...]
//                        [--translation M] [--rotation RAD] [--substeps N] [--erp E]
//                        [--push-duration S] [--perturb M] MAP.h5 ...
// A variant with penetration=1e-9 ends every check after its world is built (the cost of
// construction), mode=closing leaves out the pushes: the breakdown of the check's cost.
// Variant keys: timestep, substeps, iterations, closing_time, stages, push_duration, settle,
// pieces, erp, settle_erp, translation, rotation, rest_speed, rest_steps, penetration, torsional,
// jaw_force, warm_drives, two_friction, jaw_iterations, order (six digits: the push order),
// bound (push_free_bound 0/1), gripper_force (revolute_gripper_force 0/1), mode. Without --variant
// one variant, "default", of the options given; a variant whose name starts with "early" starts
// from ClosingCheckOptions::earlyVerdict() (the mode from --mode). --grasps N checks the first N
// labelled grasps of each map. --perturb M moves every palm by M metres along x of the object
// frame before the check (the check's sensitivity: how many verdicts a perturbation far below
// any physical tolerance changes; docs/VALIDATION.md, third round).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "taskmap/builder/map_builder.hpp"
#include "taskmap/grasp_sim/closing_check.hpp"
#include "taskmap/mapstore/grasp_contacts.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/mapstore/recorded_hand.hpp"
#include "taskmap/quality/grasp_quality.hpp"
#include "taskmap/validate/validate_map.hpp"

namespace {

using Clock = std::chrono::steady_clock;

/// CPU seconds of the calling thread (the builds count CPU time, not wall time).
double threadCpu() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Variant {
  std::string name;
  taskmap::ClosingCheckOptions options;
};

struct Tally {
  int tp = 0, fp = 0, fn = 0, tn = 0;
  long steps = 0;
  double check_s = 0.0, quality_s = 0.0, check_cpu_s = 0.0, quality_cpu_s = 0.0;
  void add(const Tally& o) {
    tp += o.tp, fp += o.fp, fn += o.fn, tn += o.tn, steps += o.steps;
    check_s += o.check_s, quality_s += o.quality_s;
    check_cpu_s += o.check_cpu_s, quality_cpu_s += o.quality_cpu_s;
  }
  int n() const { return std::max(1, tp + fp + fn + tn); }
};

void setKey(taskmap::ClosingCheckOptions* o, const std::string& key, const std::string& v) {
  const double x = std::atof(v.c_str());
  if (key == "timestep")
    o->timestep = x;
  else if (key == "substeps")
    o->substeps = std::atoi(v.c_str());
  else if (key == "iterations")
    o->solver_iterations = std::atoi(v.c_str());
  else if (key == "closing_time")
    o->closing_time = x;
  else if (key == "stages")
    o->interpolation_stages = std::atoi(v.c_str());
  else if (key == "push_duration")
    o->push_duration = x;
  else if (key == "settle")
    o->max_settle_steps = std::atoi(v.c_str());
  else if (key == "pieces")
    o->object_max_pieces = std::atoi(v.c_str());
  else if (key == "erp")
    o->contact_erp = x;
  else if (key == "settle_erp")
    o->settle_erp = x;
  else if (key == "translation")
    o->max_translation = x;
  else if (key == "rotation")
    o->max_rotation = x;
  else if (key == "rest_speed")
    o->rest_speed = x;
  else if (key == "rest_steps")
    o->rest_steps = std::atoi(v.c_str());
  else if (key == "penetration")
    o->max_penetration = x;
  else if (key == "torsional")
    o->torsional_friction = x;
  else if (key == "jaw_iterations")
    o->jaws.solver_iterations = std::atoi(v.c_str());
  else if (key == "jaw_torsional")
    o->jaws.torsional_friction = x;
  else if (key == "jaw_warm_drives")
    o->jaws.warm_start_drives = x != 0.0;
  else if (key == "warm_drives")
    o->warm_start_drives = x != 0.0;
  else if (key == "jaw_force")
    o->jaw_force = x;
  else if (key == "creep")
    o->push_bound_creep = x;
  else if (key == "bound")
    o->push_free_bound = x != 0.0;
  else if (key == "gripper_force")  // ClosingCheckOptions::revolute_gripper_force 0/1
    o->revolute_gripper_force = x != 0.0;
  else if (key == "order")  // the push order as six digits, e.g. 543210
    for (std::size_t k = 0; k < 6 && k < v.size(); ++k) o->push_order[k] = v[k] - '0';
  else if (key == "mode")
    o->mode = taskmap::closingCheckModeFromString(v);
  else
    throw std::runtime_error("unknown variant key " + key);
}

Variant parseVariant(const std::string& spec, const taskmap::ClosingCheckOptions& base) {
  Variant v{spec.substr(0, spec.find(':')), base};
  if (v.name.rfind("early", 0) == 0) {  // "early...": from the early-verdict settings
    v.options = taskmap::ClosingCheckOptions::earlyVerdict();
    v.options.mode = base.mode;
  }
  if (spec.find(':') == std::string::npos) return v;
  std::stringstream ss(spec.substr(spec.find(':') + 1));
  for (std::string kv; std::getline(ss, kv, ',');) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw std::runtime_error("variant item without '=': " + kv);
    setKey(&v.options, kv.substr(0, eq), kv.substr(eq + 1));
  }
  return v;
}

std::string handGroup(const std::string& path) {
  const std::string base = path.substr(path.find_last_of('/') + 1);
  return base.substr(0, base.find('_'));
}

void printTally(const char* what, const std::string& key, const std::string& variant,
                const Tally& t) {
  const double precision = t.tp + t.fp > 0 ? double(t.tp) / (t.tp + t.fp) : 0.0;
  const double recall = t.tp + t.fn > 0 ? double(t.tp) / (t.tp + t.fn) : 0.0;
  std::printf(
      "%s,%s,%s,TP %d,FP %d,FN %d,TN %d,precision %.3f,recall %.3f,check ms/grasp %.3f,"
      "quality ms/grasp %.3f,check CPU ms/grasp %.3f,quality CPU ms/grasp %.3f,steps/grasp %.1f\n",
      what, key.c_str(), variant.c_str(), t.tp, t.fp, t.fn, t.tn, precision, recall,
      1e3 * t.check_s / t.n(), 1e3 * t.quality_s / t.n(), 1e3 * t.check_cpu_s / t.n(),
      1e3 * t.quality_cpu_s / t.n(), double(t.steps) / t.n());
}

/// Runs every variant on the map's labelled grasps; returns a tally per variant.
std::vector<Tally> report(const std::string& path, const std::vector<Variant>& variants,
                          int max_grasps, double perturb) {
  const taskmap::TaskMapData map = taskmap::readMap(path);
  std::vector<Tally> tally(variants.size());
  if (!map.validation) {
    std::fprintf(stderr, "%s: no hold labels (run taskmap validate)\n", path.c_str());
    return tally;
  }
  const taskmap::HandModel hand = taskmap::HandModel::load(taskmap::findMapHandUrdf(map));
  const taskmap::ObjectModel object = taskmap::mapObjectModel(map);
  const auto& mp = object.massProperties();
  std::vector<std::unique_ptr<taskmap::ClosingChecker>> checkers;
  for (const Variant& v : variants) {
    const auto t_setup = Clock::now();
    checkers.push_back(std::make_unique<taskmap::ClosingChecker>(object, hand, v.options));
    std::fprintf(stderr, "%s %s: setup %.2f s, %d pieces\n", path.c_str(), v.name.c_str(),
                 std::chrono::duration<double>(Clock::now() - t_setup).count(),
                 checkers.back()->objectPieces());
  }
  const taskmap::QualityOptions qo = taskmap::buildQualityDefaults();
  int done = 0;
  for (std::size_t i = 0; i < map.grasps.size() && done < max_grasps; ++i) {
    const std::uint8_t hold = map.validation->hold[i];
    if (hold == taskmap::MapValidation::kNotTested) continue;
    ++done;
    const Eigen::VectorXd q = map.grasps.joints.row(static_cast<Eigen::Index>(i)).transpose();
    const auto tq = Clock::now();
    const double cq = threadCpu();
    (void)taskmap::evaluateGrasp(taskmap::graspContacts(map.grasps, i), mp.center_of_mass,
                                 mp.torque_scale, qo);
    const double quality_cpu_s = threadCpu() - cq;
    const double quality_s = std::chrono::duration<double>(Clock::now() - tq).count();
    for (std::size_t v = 0; v < variants.size(); ++v) {
      const auto t0 = Clock::now();
      const double c0 = threadCpu();
      taskmap::Pose palm = map.grasps.poseAt(i);
      palm.position.x() += perturb;
      const taskmap::ClosingCheckResult r = checkers[v]->check(palm, q);
      const double cpu_s = threadCpu() - c0;
      Tally& t = tally[v];
      t.check_cpu_s += cpu_s;
      t.check_s += std::chrono::duration<double>(Clock::now() - t0).count();
      t.quality_s += quality_s;
      t.quality_cpu_s += quality_cpu_s;
      t.steps += r.steps;
      const bool pass = r.holds;
      (hold ? (pass ? t.tp : t.fn) : (pass ? t.fp : t.tn))++;
      std::printf(
          "row,%s,%s,%zu,%d,%d,%.5f,%.4f,%.5f,%d,%.5f,%.5f,%d,%d,%d,%d,%.3f,%d,%d,%d,%d,%d,%d\n",
          path.c_str(), variants[v].name.c_str(), i, int(hold), int(map.validation->status[i]),
          r.translation, r.rotation, r.initial_penetration, int(pass),
          map.validation->translation[i], map.grasps.epsilon[i], r.failed_push, r.steps,
          r.settle_steps, r.closing_steps, 1e3 * cpu_s, r.push_steps[0], r.push_steps[1],
          r.push_steps[2], r.push_steps[3], r.push_steps[4], r.push_steps[5]);
    }
  }
  for (std::size_t v = 0; v < variants.size(); ++v)
    printTally("map", path, variants[v].name, tally[v]);
  std::fflush(stdout);
  return tally;
}

}  // namespace

int main(int argc, char** argv) {
  taskmap::ClosingCheckOptions options;
  options.mode = taskmap::ClosingCheckMode::kClosing;
  std::vector<std::string> maps, specs;
  int max_grasps = 1 << 30;
  double perturb = 0.0;
  try {
    for (int a = 1; a < argc; ++a) {
      const std::string arg = argv[a];
      if (arg == "--translation" && a + 1 < argc) {
        options.max_translation = std::atof(argv[++a]);
      } else if (arg == "--rotation" && a + 1 < argc) {
        options.max_rotation = std::atof(argv[++a]);
      } else if (arg == "--mode" && a + 1 < argc) {
        options.mode = taskmap::closingCheckModeFromString(argv[++a]);
      } else if (arg == "--erp" && a + 1 < argc) {
        options.contact_erp = std::atof(argv[++a]);
      } else if (arg == "--push-duration" && a + 1 < argc) {
        options.push_duration = std::atof(argv[++a]);
      } else if (arg == "--substeps" && a + 1 < argc) {
        options.substeps = std::atoi(argv[++a]);
      } else if (arg == "--grasps" && a + 1 < argc) {
        max_grasps = std::atoi(argv[++a]);
      } else if (arg == "--perturb" && a + 1 < argc) {
        perturb = std::atof(argv[++a]);
      } else if (arg == "--variant" && a + 1 < argc) {
        specs.push_back(argv[++a]);
      } else {
        maps.push_back(arg);
      }
    }
    std::vector<Variant> variants;
    for (const std::string& s : specs) variants.push_back(parseVariant(s, options));
    if (variants.empty()) variants.push_back({"default", options});
    for (const Variant& v : variants) v.options.validate();
    std::map<std::string, std::vector<Tally>> by_hand;
    std::vector<Tally> all(variants.size());
    for (const std::string& m : maps) {
      try {
        const std::vector<Tally> t = report(m, variants, max_grasps, perturb);
        auto& h = by_hand[handGroup(m)];
        h.resize(variants.size());
        for (std::size_t v = 0; v < variants.size(); ++v) h[v].add(t[v]), all[v].add(t[v]);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: %s\n", m.c_str(), e.what());
      }
    }
    for (const auto& [hand, t] : by_hand)
      for (std::size_t v = 0; v < variants.size(); ++v)
        printTally("hand", hand, variants[v].name, t[v]);
    for (std::size_t v = 0; v < variants.size(); ++v)
      printTally("all", "all", variants[v].name, all[v]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "closing_check_report: %s\n", e.what());
    return 2;
  }
  return 0;
}
