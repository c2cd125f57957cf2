// What to check when a build stores no grasp.
#include "build_diagnosis.hpp"

#include <algorithm>
#include <cstdio>

#include "taskmap/builder/size_check.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/meshes/object_size.hpp"

namespace taskmap::detail {
namespace {

std::string num(double v, const char* fmt = "%.3g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

/// What an outcome means for the setup, and what to look at.
std::string adviceFor(const std::string& outcome) {
  if (outcome == "no_palm_contact")
    return "the palm never touched the object when the hand was pulled back: check that the "
           "sidecar's approach_axis points from the palm toward the object (a reversed axis "
           "backs away), that the palm link has geometry facing the object, and that the "
           "preshape opens the fingers wide enough for the palm to reach it";
  if (outcome == "no_finger_contact")
    return "closing ended at the joint limits without a finger touching: check that the "
           "sidecar's approach_axis points from the palm toward the object between the fingers "
           "(a reversed axis leaves the object behind the palm), the closing direction (toward "
           "lower/upper), and the preshape opening against the object size";
  if (outcome == "not_retractable")
    return "the hand could not be pulled out of the object: check the approach_axis sign and "
           "geometry fixed to the palm in front of it (e.g. collision capsules of a flange); "
           "`taskmap hand-info` shows both";
  if (outcome == "self_collision")
    return "hand links collide with each other: check the preshape and the closing limits";
  if (outcome == "step_limit")
    return "closing did not settle: check for degenerate collision geometry";
  if (outcome == "not_force_closure")
    return "grasps closed but none reached force closure: check the friction coefficient, the "
           "preshape and the object size against the hand";
  if (outcome == "unbalanced")
    return "grasps closed but the hold filter found none whose squeeze holds the free object: "
           "check the preshape and closing against the object size, or build without "
           "--hold-filter";
  if (outcome == "weak_squeeze")
    return "grasps closed but the fingers stopped so near their preshape that none presses the "
           "object with the least squeeze force: check the preshape opening against the object "
           "size, or build with --min-squeeze-force 0";
  if (outcome == "pushed")
    return "grasps reached force closure but the closing check found none whose closing keeps "
           "the free object in place: check the preshape and closing against the object size, "
           "or build without --closing-check";
  if (outcome == "not_holding")
    return "grasps reached force closure but none held in the physics hold test: raise "
           "--trials, try --hold-test nominal, or build the untested force-closure map with "
           "--hold-test off (`taskmap validate --trace` shows why a grasp fails)";
  return "check the hand sidecar and the object";
}

}  // namespace

std::string noGraspMessage(const std::map<std::string, std::uint64_t>& outcomes,
                           std::uint64_t trials, const ObjectModel& object, const HandModel& hand) {
  std::string dominant = "none";
  std::uint64_t most = 0;
  for (const auto& [name, count] : outcomes)
    if (count > most) {
      most = count;
      dominant = name;
    }
  const double share = trials > 0 ? 100.0 * static_cast<double>(most) / trials : 0.0;
  const std::string head = "no grasp stored after " + std::to_string(trials) + " trials: ";
  std::string outcome = num(share, "%.0f") + "% ended " + dominant + "; " + adviceFor(dominant);
  const auto tested = outcomes.find("not_holding");
  if (dominant != "not_holding" && tested != outcomes.end() && tested->second > 0)
    outcome +=
        "; " + std::to_string(tested->second) + " reached force closure, and " +
        adviceFor("not_holding").substr(std::string("grasps reached force closure but ").size());
  // Suspects ranked by evidence: an object that dwarfs the hand (or is thinner than its
  // fingers) explains any outcome, so its size comes first; otherwise the outcome's advice.
  const ObjectSizeCheck size = checkObjectSize(object, hand);
  const bool size_suspect =
      size.reach > 0 && (size.extent > kDwarfReachRatio * size.reach || size.too_small);
  const std::string advice =
      scaleAdvice(size.extent, object.scale(), std::max(size.finger, kGraspableMinExtent),
                  kMaxReachRatio * size.reach, size.reach);
  if (size_suspect)
    return head + "first suspect, the size: " + size.sizes + "; " + advice + ". Then: " + outcome;
  return head + outcome + ". Units: the object is " + num(size.extent) +
         " m across, the open hand reaches " + num(size.reach) +
         " m (--scale converts file units to metres)";
}

}  // namespace taskmap::detail
