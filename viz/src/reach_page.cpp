// The trajectory page's data: bodies and their primitives, poses per step, object, costs, and
// the map's hand closing on the object (link poses computed here; viewer_reach.js draws them).
#include "taskmap/viz/reach_page.hpp"

#include <algorithm>
#include <cmath>

#include "hand_json.hpp"
#include "page.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

using viz_detail::flat;
using viz_detail::rounded;

nlohmann::json shapesJson(const TrajectoryRecord& r, int decimals) {
  nlohmann::json out = nlohmann::json::array();
  for (const TrajectoryShape& s : r.shapes)
    out.push_back({{"b", s.body},
                   {"c", flat(s.center.transpose(), decimals)},
                   {"axes", flat(s.axes, decimals)},  // row by row
                   {"hu", rounded(s.half_u, decimals)},
                   {"hv", rounded(s.half_v, decimals)},
                   {"r", rounded(s.radius, decimals)}});
  return out;
}

nlohmann::json planJson(const TrajectoryRecord& r, int decimals) {
  return {{"map_path", r.map_path},
          {"start_cluster", r.start_cluster},
          {"cluster", r.cluster},
          {"grasp_index", r.grasp_index},
          {"quality_peak", r.quality_peak},
          {"cost_terms", r.cost_terms},
          {"cost_history", flat(r.cost_history, decimals + 2)},
          {"proximity", flat(r.proximity_over_movement, decimals + 2)},
          {"quality", flat(r.quality_over_movement, decimals + 2)}};
}

/// {stage [S], close_from, close_s, links L, poses [stages x L x 7] (palm frame, x y z qw qx qy
/// qz), joints [stages x J]}.
nlohmann::json motionJson(const ReachHandMotion& m, double dt, int decimals) {
  nlohmann::json poses = nlohmann::json::array(), joints = nlohmann::json::array();
  for (std::size_t k = 0; k < m.link_poses.size(); ++k) {
    for (const Eigen::Isometry3d& t : m.link_poses[k])
      for (const auto& v : viz_detail::poseJson(Pose::fromIsometry(t), decimals))
        poses.push_back(v);
    joints.push_back(flat(m.joints[k].transpose(), decimals + 2));
  }
  return {{"stage", m.stage},
          {"close_from", m.close_from},
          {"close_s", rounded(static_cast<double>(m.stage.size() - 1 - m.close_from) * dt, 4)},
          {"links", m.link_poses.empty() ? 0 : m.link_poses.front().size()},
          {"poses", poses},
          {"joints", joints}};
}

void checkInput(const ReachPageInput& input) {
  if (input.trajectory == nullptr) throw Error("reach page: no trajectory given");
  input.trajectory->validate();
}

}  // namespace

ReachHandMotion reachHandMotion(const HandModel& hand, const Eigen::VectorXd& grasp_joints,
                                std::size_t rows, double dt, double close_s) {
  const Eigen::VectorXd open = hand.preshape();
  if (grasp_joints.size() != open.size() || !grasp_joints.allFinite())
    throw Error("reach page: the grasp has " + std::to_string(grasp_joints.size()) +
                " joint values, hand '" + hand.name() + "' has " + std::to_string(open.size()) +
                " actuated joints");
  if (rows < 1) throw Error("reach page: the trajectory has no steps");
  if (!(dt > 0.0) || !(close_s > 0.0) || !std::isfinite(dt / close_s))
    throw Error("reach page: dt and the closing time must be finite and > 0");
  // Closing steps: close_s / dt of them, at most the whole movement; stage k at step
  // rows - 1 - n + k.
  const double wanted = std::round(close_s / dt);
  const auto n = static_cast<std::size_t>(std::min(wanted, static_cast<double>(rows - 1)));
  ReachHandMotion m;
  m.close_from = rows - 1 - n;
  m.stage.resize(rows);
  for (std::size_t t = 0; t < rows; ++t)
    m.stage[t] = t > m.close_from ? static_cast<int>(t - m.close_from) : 0;
  for (std::size_t k = 0; k <= n; ++k) {
    const double x = n == 0 ? 1.0 : static_cast<double>(k) / static_cast<double>(n);
    const double s = x * x * (3.0 - 2.0 * x);  // smoothstep: starts and ends at rest
    m.joints.push_back(open + s * (grasp_joints - open));
    m.link_poses.push_back(hand.linkPoses(m.joints.back()));
  }
  return m;
}

std::string reachPageHtml(const ReachPageInput& input, const PageOptions& options) {
  options.validate();
  checkInput(input);
  const TrajectoryRecord& record = *input.trajectory;
  const int d = options.decimals;
  nlohmann::json data = {{"kind", "reach"},
                         {"robot", record.robot},
                         {"hand", record.hand},
                         {"dt", record.dt},
                         {"rows", record.rows()},
                         {"joint_names", record.joint_names},
                         {"joints", flat(record.joints, d)},
                         {"palm_world", flat(record.palm_world, d)},
                         {"object",
                          {{"name", record.object_name},
                           {"pose", viz_detail::poseJson(record.object_pose, d)},
                           {"v", flat(record.object_vertices, d)},
                           {"f", viz_detail::flatInt(record.object_faces)}}},
                         {"bodies",
                          {{"names", record.body_names},
                           {"parent", record.body_parents},
                           {"role", record.body_roles},
                           {"poses", flat(record.body_poses, d)}}},
                         {"shapes", shapesJson(record, d)},
                         {"plan", planJson(record, d)},
                         {"map_hand", nullptr},
                         {"hand_motion", nullptr},
                         {"hand_note", input.note}};
  if (input.hand != nullptr) {
    const ReachHandMotion m =
        reachHandMotion(*input.hand, input.grasp_joints, record.rows(), record.dt, input.close_s);
    data["map_hand"] = viz_detail::handJson(*input.hand, d);
    data["hand_motion"] = motionJson(m, record.dt, d);
  }
  const std::string title = options.title.empty()
                                ? "taskmap reach: " + record.robot + " -> " + record.object_name
                                : options.title;
  return viz_detail::assemblePage(title, "viewer_reach_js", data);
}

std::string reachPageHtml(const TrajectoryRecord& record, const PageOptions& options) {
  ReachPageInput input;
  input.trajectory = &record;
  input.note = "no hand model given";
  return reachPageHtml(input, options);
}

void writeReachPage(const ReachPageInput& input, const std::string& path,
                    const PageOptions& options) {
  viz_detail::writePage(reachPageHtml(input, options), path);
}

void writeReachPage(const TrajectoryRecord& record, const std::string& path,
                    const PageOptions& options) {
  viz_detail::writePage(reachPageHtml(record, options), path);
}

}  // namespace taskmap
