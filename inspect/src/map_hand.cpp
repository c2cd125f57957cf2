// The map's hand for pictures and scene files (map_hand.hpp).
#include "taskmap/inspect/map_hand.hpp"

#include <filesystem>

#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"
#include "taskmap/inspect/hand_check.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/meshes/object_model.hpp"

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

namespace {

/// The part of a map that findMapHand reads (its hand and the recorded model path), rebuilt from
/// a trajectory's /plan/grasp.
TaskMapData handOnlyMap(const TrajectoryRecord& r) {
  TaskMapData map;
  map.hand.name = r.map_hand;
  map.hand.urdf_sha256 = r.map_hand_sha256;
  map.hand.joint_names = r.grasp_joint_names;
  if (!r.map_hand_path.empty())
    map.sampling.params_json = nlohmann::json{{"hand", r.map_hand_path}}.dump();
  return map;
}

TrajectoryHand notFound(const std::string& why) {
  TrajectoryHand out;
  out.found.status = MapHandResult::Status::kNotFound;
  out.found.message = why;
  return out;
}

/// A trajectory written before /plan/grasp: the hand and joints from its map, when unchanged.
TrajectoryHand handFromMapFile(const TrajectoryRecord& r, const MapHandOptions& options) {
  const std::string again = "; write the trajectory again with `taskmap reach --map ... -o FILE`";
  std::error_code ec;
  if (!std::filesystem::is_regular_file(r.map_path, ec))
    return notFound("the trajectory records no grasp joint values and its map '" + r.map_path +
                    "' is not there" + again);
  if (sha256File(r.map_path) != r.map_sha256)
    return notFound("the trajectory records no grasp joint values and its map '" + r.map_path +
                    "' has changed since the plan (SHA-256 differs)" + again);
  const TaskMapData map = readMap(r.map_path);
  if (r.grasp_index < 0 || static_cast<std::size_t>(r.grasp_index) >= map.grasps.size() ||
      map.grasps.joints.cols() == 0)
    return notFound("the map '" + r.map_path + "' has no joint values for grasp " +
                    std::to_string(r.grasp_index));
  TrajectoryHand out;
  out.found = findMapHand(map, options);
  if (out.found.hand) out.grasp_joints = graspPosture(map, r.grasp_index).joints;
  return out;
}

}  // namespace

TrajectoryHand findTrajectoryHand(const TrajectoryRecord& record, const MapHandOptions& options) {
  if (record.grasp_joint_names.empty()) return handFromMapFile(record, options);
  TrajectoryHand out;
  out.found = findMapHand(handOnlyMap(record), options);
  if (out.found.hand) out.grasp_joints = record.grasp_joints;
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

}  // namespace taskmap
