// The trajectory page's data: bodies and their primitives, poses per step, object, costs.
#include "taskmap/viz/reach_page.hpp"

#include "page.hpp"

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
          {"cost_terms", r.cost_terms},
          {"cost_history", flat(r.cost_history, decimals + 2)},
          {"proximity", flat(r.proximity_over_movement, decimals + 2)},
          {"quality", flat(r.quality_over_movement, decimals + 2)}};
}

}  // namespace

std::string reachPageHtml(const TrajectoryRecord& record, const PageOptions& options) {
  options.validate();
  record.validate();
  const int d = options.decimals;
  const nlohmann::json data = {{"kind", "reach"},
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
                               {"plan", planJson(record, d)}};
  const std::string title = options.title.empty()
                                ? "taskmap reach: " + record.robot + " -> " + record.object_name
                                : options.title;
  return viz_detail::assemblePage(title, "viewer_reach_js", data);
}

void writeReachPage(const TrajectoryRecord& record, const std::string& path,
                    const PageOptions& options) {
  viz_detail::writePage(reachPageHtml(record, options), path);
}

}  // namespace taskmap
