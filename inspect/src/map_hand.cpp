// The map's hand for pictures and scene files (map_hand.hpp).
#include "taskmap/inspect/map_hand.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"
#include "taskmap/inspect/hand_check.hpp"

namespace taskmap {

namespace {

/// The build parameters a map records (params_json), {} when they are not a JSON object.
nlohmann::json mapParams(const TaskMapData& map) {
  try {
    const nlohmann::json j = nlohmann::json::parse(map.sampling.params_json);
    if (j.is_object()) return j;
  } catch (const nlohmann::json::exception&) {
    // A map whose params are not JSON (imported, hand-made): nothing is recorded.
  }
  return nlohmann::json::object();
}

/// Does the URDF at path hold the map's hand (same SHA-256)?
bool matchesHand(const std::string& path, const std::string& sha256) {
  if (path.empty() || !std::filesystem::is_regular_file(path)) return false;
  try {
    return HandModel::load(path).urdfSha256() == sha256;
  } catch (const Error&) {
    return false;
  }
}

}  // namespace

void MapHandOptions::validate() const {
  if (!hand.empty() && !std::filesystem::is_regular_file(hand))
    throw Error("hand '" + hand + "' is not a file; give the URDF of the hand");
}

std::string findMapHandUrdf(const TaskMapData& map, const std::string& hands_dir) {
  const nlohmann::json params = mapParams(map);
  const auto it = params.find("hand");
  const std::string recorded = it != params.end() && it->is_string() ? it->get<std::string>() : "";
  if (matchesHand(recorded, map.hand.urdf_sha256)) return recorded;
  // A map built elsewhere (another checkout, the install tree): the bundled hand with that content.
  std::vector<std::string> candidates;
  std::error_code ec;
  if (!hands_dir.empty()) {
    for (const auto& entry : std::filesystem::directory_iterator(hands_dir, ec)) {
      const std::string name = entry.path().filename().string();
      candidates.push_back((entry.path() / (name + ".urdf")).string());
    }
  }
  std::sort(candidates.begin(), candidates.end());
  for (const std::string& urdf : candidates)
    if (matchesHand(urdf, map.hand.urdf_sha256)) return urdf;
  throw Error("the map's hand '" + map.hand.name + "' (URDF SHA-256 " +
              map.hand.urdf_sha256.substr(0, 12) + "...) is neither at the recorded path '" +
              recorded + "'" +
              (hands_dir.empty() ? std::string() : " nor a bundled hand under " + hands_dir));
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
