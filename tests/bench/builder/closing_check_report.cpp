// closing_check_report: how well the closing check (closing with the object free,
// grasp_sim/closing_check.hpp) predicts the physics hold test. For maps labelled by `taskmap
// validate`, prints one CSV row per tested grasp (the object's motion in the check, its verdict,
// the validator's label and status), then per map the confusion matrix and the check's cost
// per grasp against the quality stage's (evaluateGrasp) on the same grasps, in the same process.
// Not a unit test.
//
//   closing_check_report [--mode closing|pushes] [--translation M] [--rotation RAD]
//                        [--substeps N] [--erp E] [--push-duration S] MAP.h5 ...
#include <chrono>
#include <cstdio>
#include <cstdlib>
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

void report(const std::string& path, const taskmap::ClosingCheckOptions& options) {
  const taskmap::TaskMapData map = taskmap::readMap(path);
  if (!map.validation) {
    std::fprintf(stderr, "%s: no hold labels (run taskmap validate)\n", path.c_str());
    return;
  }
  const taskmap::HandModel hand = taskmap::HandModel::load(taskmap::findMapHandUrdf(map));
  const taskmap::ObjectModel object = taskmap::mapObjectModel(map);
  const auto& mp = object.massProperties();
  const auto t_setup = Clock::now();
  const taskmap::ClosingChecker checker(object, hand, options);
  const double setup_s = std::chrono::duration<double>(Clock::now() - t_setup).count();
  int tp = 0, fp = 0, fn = 0, tn = 0;
  double check_s = 0.0, quality_s = 0.0, worst_placement = 0.0;
  const taskmap::QualityOptions qo = taskmap::buildQualityDefaults();
  for (std::size_t i = 0; i < map.grasps.size(); ++i) {
    const std::uint8_t hold = map.validation->hold[i];
    if (hold == taskmap::MapValidation::kNotTested) continue;
    const Eigen::VectorXd q = map.grasps.joints.row(static_cast<Eigen::Index>(i)).transpose();
    const auto t0 = Clock::now();
    const taskmap::ClosingCheckResult r = checker.check(map.grasps.poseAt(i), q);
    const auto t1 = Clock::now();
    (void)taskmap::evaluateGrasp(taskmap::graspContacts(map.grasps, i), mp.center_of_mass,
                                 mp.torque_scale, qo);
    const auto t2 = Clock::now();
    check_s += std::chrono::duration<double>(t1 - t0).count();
    quality_s += std::chrono::duration<double>(t2 - t1).count();
    worst_placement = std::max(worst_placement, r.placement_error);
    const bool pass = r.holds;
    (hold ? (pass ? tp : fn) : (pass ? fp : tn))++;
    std::printf("row,%s,%zu,%d,%d,%.5f,%.4f,%.5f,%d,%.5f,%.5f,%d,%d\n", path.c_str(), i, int(hold),
                int(map.validation->status[i]), r.translation, r.rotation, r.initial_penetration,
                int(pass), map.validation->translation[i], map.grasps.epsilon[i], r.failed_push,
                r.steps);
  }
  const int n = std::max(1, tp + fp + fn + tn);
  std::printf(
      "map,%s,TP %d,FP %d,FN %d,TN %d,check ms/grasp %.2f,quality ms/grasp %.2f,setup s %.2f,"
      "pieces %d,placement error %.2g m\n",
      path.c_str(), tp, fp, fn, tn, 1e3 * check_s / n, 1e3 * quality_s / n, setup_s,
      checker.objectPieces(), worst_placement);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  taskmap::ClosingCheckOptions options;
  options.mode = taskmap::ClosingCheckMode::kClosing;
  std::vector<std::string> maps;
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
    } else {
      maps.push_back(arg);
    }
  }
  for (const std::string& m : maps) {
    try {
      report(m, options);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", m.c_str(), e.what());
    }
  }
  return 0;
}
