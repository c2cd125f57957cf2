// hold_filter_report: how well the build's hold filter (squeeze balance, hold_filter.hpp)
// predicts the physics hold test. For maps labelled by `taskmap validate`, prints one CSV row
// per tested grasp (the filter's residuals and verdict against the validator's label), then per
// map the confusion matrix and the filter's cost against the quality stage's (evaluateGrasp)
// on the same contacts, in the same process. Not a unit test.
//
//   hold_filter_report [--tolerance T] [--push-tolerance T] [--joint-weight W] [--no-push]
//                      [--kp-gripper] MAP.h5 ...
// --kp-gripper drives a one-joint revolute gripper with kp_revolute, as before 2026-11-27
// (HoldFilterOptions::revolute_gripper_force false). Each row ends with the grasp's squeeze force
// in newtons (graspSqueezeForce, the build's squeeze-force test: docs/METHOD.md §4e).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "taskmap/builder/hold_filter.hpp"
#include "taskmap/mapstore/grasp_contacts.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/mapstore/recorded_hand.hpp"
#include "taskmap/quality/grasp_quality.hpp"
#include "taskmap/validate/validate_map.hpp"

namespace {

using Clock = std::chrono::steady_clock;

void report(const std::string& path, const taskmap::HoldFilterOptions& options) {
  const taskmap::TaskMapData map = taskmap::readMap(path);
  if (!map.validation) {
    std::fprintf(stderr, "%s: no hold labels (run taskmap validate)\n", path.c_str());
    return;
  }
  const taskmap::HandModel hand = taskmap::HandModel::load(taskmap::findMapHandUrdf(map));
  const taskmap::ObjectModel object = taskmap::mapObjectModel(map);
  const auto& mp = object.massProperties();
  int tp = 0, fp = 0, fn = 0, tn = 0;
  double filter_s = 0.0, quality_s = 0.0;
  taskmap::QualityOptions qo;
  for (std::size_t i = 0; i < map.grasps.size(); ++i) {
    const std::uint8_t hold = map.validation->hold[i];
    if (hold == taskmap::MapValidation::kNotTested) continue;
    const std::vector<taskmap::Contact> contacts = taskmap::graspContacts(map.grasps, i);
    const Eigen::VectorXd q = map.grasps.joints.row(static_cast<Eigen::Index>(i)).transpose();
    const auto t0 = Clock::now();
    const taskmap::SqueezeDrive drive =
        taskmap::squeezeDrive(hand, map.grasps.poseAt(i), q, contacts, options);
    const taskmap::SqueezeBalanceResult r = taskmap::squeezeBalance(
        contacts, drive, mp.center_of_mass, mp.torque_scale, options.balance);
    const auto t1 = Clock::now();
    (void)taskmap::evaluateGrasp(contacts, mp.center_of_mass, mp.torque_scale, qo);
    const auto t2 = Clock::now();
    filter_s += std::chrono::duration<double>(t1 - t0).count();
    quality_s += std::chrono::duration<double>(t2 - t1).count();
    const bool pass = r.balanced;
    (hold ? (pass ? tp : fn) : (pass ? fp : tn))++;
    const double squeeze = taskmap::graspSqueezeForce(hand, map.grasps.poseAt(i), q, contacts);
    std::printf("row,%s,%zu,%d,%d,%.4f,%.4f,%d,%d,%.5f,%zu,%.4f\n", path.c_str(), i, int(hold),
                int(map.validation->status[i]), r.squeeze_residual, r.push_residual, r.failed_push,
                int(pass), map.grasps.epsilon[i], contacts.size(), squeeze);
  }
  std::printf("map,%s,TP %d,FP %d,FN %d,TN %d,filter us/grasp %.1f,quality us/grasp %.1f\n",
              path.c_str(), tp, fp, fn, tn, 1e6 * filter_s / std::max(1, tp + fp + fn + tn),
              1e6 * quality_s / std::max(1, tp + fp + fn + tn));
}

}  // namespace

int main(int argc, char** argv) {
  taskmap::HoldFilterOptions options;
  std::vector<std::string> maps;
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--tolerance" && a + 1 < argc) {
      options.balance.squeeze_tolerance = std::atof(argv[++a]);
    } else if (arg == "--push-tolerance" && a + 1 < argc) {
      options.balance.push_tolerance = std::atof(argv[++a]);
    } else if (arg == "--joint-weight" && a + 1 < argc) {
      options.balance.push_joint_weight = std::atof(argv[++a]);
    } else if (arg == "--squeeze-weight" && a + 1 < argc) {
      options.balance.squeeze_joint_weight = std::atof(argv[++a]);
    } else if (arg == "--no-push") {
      options.balance.push_force = 0.0;
    } else if (arg == "--kp-gripper") {
      options.revolute_gripper_force = false;
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
