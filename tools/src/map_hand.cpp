// The map's hand for pictures and scene files (map_hand.hpp).
#include "map_hand.hpp"

#include <filesystem>
#include <iostream>

#include "hand_check.hpp"
#include "reach_resimulate.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap::cli {

std::optional<HandModel> mapHand(const TaskMapData& map, const std::string& hand,
                                 const std::string& who) {
  std::optional<HandModel> out;
  if (!hand.empty()) {
    out = HandModel::load(std::filesystem::exists(hand) ? hand : bundledHandUrdf(hand));
  } else {
    try {
      out = HandModel::load(mapHandUrdf(map));
    } catch (const Error& e) {
      std::cerr << who << ": warning: " << e.what() << "; drawing no hand (give --hand)\n";
      return std::nullopt;
    }
  }
  if (out->jointNames() != map.hand.joint_names) {
    std::cerr << who << ": warning: hand '" << out->name()
              << "' has other actuated joints than the map's hand '" << map.hand.name
              << "'; drawing no hand\n";
    return std::nullopt;
  }
  return out;
}

GraspPosture graspPosture(const TaskMapData& map, std::size_t i) {
  if (i >= map.grasps.size())
    throw Error("grasp " + std::to_string(i) + " is out of range (the map has " +
                std::to_string(map.grasps.size()) + " grasps)");
  GraspPosture p;
  p.palm_pose = map.grasps.poseAt(i).toIsometry();
  p.joints = map.grasps.joints.row(static_cast<Eigen::Index>(i)).transpose();
  return p;
}

std::vector<PosedShapePoints> posedShapePoints(const HandModel& hand, const GraspPosture& p) {
  std::vector<PosedShapePoints> out;
  const std::vector<Eigen::Isometry3d> poses = hand.linkPoses(p.joints);
  for (std::size_t li = 0; li < hand.links().size(); ++li) {
    for (const CollisionShape& s : hand.links()[li].shapes) {
      const Eigen::Isometry3d t = p.palm_pose * poses[li] * s.origin;
      PosedShapePoints shape{static_cast<int>(li), {}};
      for (const Eigen::Vector3d& x : shapePoints(s)) shape.points.push_back(t * x);
      out.push_back(std::move(shape));
    }
  }
  return out;
}

}  // namespace taskmap::cli
