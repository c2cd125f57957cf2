// The map's hand for pictures and scene files (map_hand.hpp).
#include "taskmap/inspect/map_hand.hpp"

#include <filesystem>

#include "taskmap/core/error.hpp"
#include "taskmap/inspect/hand_check.hpp"

namespace taskmap {

void MapHandOptions::validate() const {
  if (!hand.empty() && !std::filesystem::is_regular_file(hand))
    throw Error("hand '" + hand + "' is not a file; give the URDF of the hand");
}

MapHandResult findMapHand(const TaskMapData& map, const MapHandOptions& options) {
  options.validate();
  MapHandResult r;
  if (!options.hand.empty()) {
    r.hand = HandModel::load(options.hand);
  } else {
    try {
      r.hand = HandModel::load(findMapHandUrdf(map, options.hands_dir));
    } catch (const Error& e) {
      r.status = MapHandResult::Status::kNotFound;
      r.message = e.what();
      return r;
    }
  }
  if (r.hand->jointNames() != map.hand.joint_names) {
    r.status = MapHandResult::Status::kOtherJoints;
    r.message = "hand '" + r.hand->name() + "' has other actuated joints than the map's hand '" +
                map.hand.name + "'";
    r.hand.reset();
    return r;
  }
  r.status = MapHandResult::Status::kLoaded;
  return r;
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

}  // namespace taskmap
