// The planned reach as a trajectory record (mapstore/TRAJECTORY.md).
#include "taskmap/reaching/trajectory_record.hpp"

#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/mapstore/recorded_hand.hpp"
#include "taskmap/meshes/object_model.hpp"

#ifndef TASKMAP_VERSION
#define TASKMAP_VERSION "unknown"
#endif

namespace taskmap {
namespace {

void addBodies(const RobotModel& robot, const std::string& object_name, bool object_mesh,
               TrajectoryRecord& r) {
  const std::vector<RobotBody>& bodies = robot.bodies();
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const RobotBody& b = bodies[i];
    r.body_names.push_back(b.name);
    r.body_parents.push_back(b.parent);
    r.body_roles.push_back(b.role == BodyRole::kRobot ? 0 : b.role == BodyRole::kHand ? 1 : 2);
    if (object_mesh && b.name == object_name) continue;  // drawn by its mesh instead
    for (const Primitive& p : b.shapes) {
      TrajectoryShape s;
      s.body = static_cast<int>(i);
      s.type = p.type == PrimitiveType::kCapsule ? TrajectoryShapeType::kCapsule
                                                 : TrajectoryShapeType::kSweptRectangle;
      s.center = p.center;
      s.axes = p.axes;
      s.half_u = p.half_u;
      s.half_v = p.half_v;
      s.radius = p.radius;
      r.shapes.push_back(s);
    }
  }
}

void addSteps(const RobotModel& robot, int palm, int object, const std::vector<Eigen::VectorXd>& q,
              TrajectoryRecord& r) {
  const auto s = static_cast<Eigen::Index>(q.size());
  const auto nb = static_cast<Eigen::Index>(robot.bodies().size());
  r.joints.resize(s, robot.dofs());
  r.palm_world.resize(s, 7);
  r.palm_object.resize(s, 7);
  r.body_poses.resize(s, 7 * nb);
  Kinematics kin(robot);
  for (Eigen::Index t = 0; t < s; ++t) {
    kin.update(q[static_cast<std::size_t>(t)]);
    r.joints.row(t) = q[static_cast<std::size_t>(t)].transpose();
    r.palm_world.row(t) = Pose::fromIsometry(kin.pose(palm)).toVector7().transpose();
    r.palm_object.row(t) = poseInFrameOf(kin, palm, object).toVector7().transpose();
    for (Eigen::Index b = 0; b < nb; ++b)
      r.body_poses.row(t).segment<7>(7 * b) =
          Pose::fromIsometry(kin.pose(static_cast<int>(b))).toVector7().transpose();
  }
  r.object_pose = Pose::fromIsometry(kin.pose(object));
}

void addHistory(const ClusterPlan& b, TrajectoryRecord& r) {
  r.cost_terms = {"total",    "path_length", "end_velocity", "collision",         "joint_limit",
                  "terminal", "proximity",   "quality",      "nearest_distance_m"};
  const auto& h = b.optimization.history;
  r.cost_history.resize(static_cast<Eigen::Index>(h.size()), 9);
  for (std::size_t i = 0; i < h.size(); ++i)
    r.cost_history.row(static_cast<Eigen::Index>(i)) << h[i].total, h[i].path_length,
        h[i].end_velocity, h[i].collision, h[i].joint_limit, h[i].terminal, b.proximity.at(i),
        b.quality.at(i), b.nearest_distance.at(i);
}

/// The map's hand and the chosen grasp's joint values, when the map records them.
void addGrasp(const TaskMapData& data, std::int64_t grasp, TrajectoryRecord& r) {
  if (grasp < 0 || static_cast<std::size_t>(grasp) >= data.grasps.size() ||
      data.hand.joint_names.empty() ||
      data.grasps.joints.cols() != static_cast<Eigen::Index>(data.hand.joint_names.size()))
    return;
  r.map_hand = data.hand.name;
  r.map_hand_sha256 = data.hand.urdf_sha256;
  r.map_hand_path = recordedHandPath(data);
  r.grasp_joint_names = data.hand.joint_names;
  r.grasp_joints = data.grasps.joints.row(static_cast<Eigen::Index>(grasp)).transpose();
}

}  // namespace

TrajectoryRecord trajectoryRecord(const RobotModel& robot, int palm, int object, const TaskMap& map,
                                  const ClusterPlan& b, const MovementTerms& movement,
                                  const TrajectorySource& source) {
  TrajectoryRecord r;
  r.generator = std::string("taskmap ") + TASKMAP_VERSION;
  r.created_utc = mapCreationTime();
  r.robot = source.robot;
  r.hand = source.hand;
  r.dt = source.dt;
  r.joint_names = robot.dofNames();
  addSteps(robot, palm, object, b.optimization.cost.q, r);
  const TaskMapData& data = map.data();
  r.object_name = robot.bodies()[static_cast<std::size_t>(object)].name;
  r.object_vertices = data.object.vertices;
  r.object_faces = data.object.faces;
  addBodies(robot, r.object_name, data.object.vertices.rows() > 0, r);
  r.map_path = source.map_path;
  r.map_sha256 = sha256File(source.map_path);
  r.start_cluster = b.cluster;
  r.cluster = b.grasp_cluster;
  r.grasp_index = b.grasp_index;
  r.quality_peak = source.quality_peak;
  addGrasp(data, b.grasp_index, r);
  addHistory(b, r);
  r.proximity_over_movement = Eigen::Map<const Eigen::VectorXd>(
      movement.proximity.data(), static_cast<Eigen::Index>(movement.proximity.size()));
  r.quality_over_movement = Eigen::Map<const Eigen::VectorXd>(
      movement.quality.data(), static_cast<Eigen::Index>(movement.quality.size()));
  return r;
}

}  // namespace taskmap
