#pragma once
// Shared by the viz tests: a map with one grasp of a real hand beside a cube, a small
// trajectory, the page's JSON data block, and headless Chromium.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/mapstore/task_map_data.hpp"
#include "taskmap/mapstore/trajectory_file.hpp"

namespace taskmap::testing {

/// The humanoid hand shipped with taskmap.
inline HandModel humanoidHand() {
  return HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf");
}

/// A cube of side 2 * half centred at the origin, as a map object.
inline MapObject cubeObject(double half) {
  MapObject o;
  o.name = "cube";
  o.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i)
    o.vertices.row(i) << (i & 1 ? half : -half), (i & 2 ? half : -half), (i & 4 ? half : -half);
  o.faces.resize(12, 3);
  o.faces << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4,
      6, 1, 3, 5, 3, 7, 5;
  o.volume = 8 * half * half * half;
  o.torque_scale = std::sqrt(3.0) * half;
  return o;
}

/// A map with one closed grasp of `hand` whose palm sits at `palm` and approaches the origin.
inline TaskMapData oneGraspMap(const HandModel& hand, const Eigen::Vector3d& palm) {
  TaskMapData m;
  m.generator = "viz test";
  m.object = cubeObject(0.04);
  m.hand.name = hand.name();
  m.hand.urdf_sha256 = hand.urdfSha256();
  m.hand.joint_names = hand.jointNames();
  for (const HandLink& l : hand.links()) m.hand.link_names.push_back(l.name);
  Pose p;
  p.position = palm;
  p.orientation = Eigen::Quaterniond::FromTwoVectors(hand.approachAxis(), -palm.normalized());
  if (p.orientation.w() < 0) p.orientation.coeffs() *= -1.0;
  MapGrasps& g = m.grasps;
  g.pose = p.toVector7().transpose();
  g.joints = hand.preshape().transpose();
  g.force_closure = {1};
  g.epsilon = {0.125};
  g.volume = {0.001};
  g.contact_offsets = {0, 1};
  g.contact_points = (palm.normalized() * 0.04).transpose();
  g.contact_normals = palm.normalized().transpose();
  g.contact_depths = {0.001};
  g.contact_links = {hand.palmLink()};
  return m;
}

/// A short trajectory: two robot links, a hand body, a table, a cube object.
inline TrajectoryRecord smallTrajectory() {
  const int s = 11;
  TrajectoryRecord r;
  r.generator = "viz test";
  r.robot = "panda";
  r.hand = "humanoid";
  r.joint_names = {"j1"};
  r.joints.resize(s, 1);
  r.palm_world.resize(s, 7);
  r.palm_object.resize(s, 7);
  r.body_names = {"base", "arm", "hand/palm", "table"};
  r.body_parents = {-1, 0, 1, -1};
  r.body_roles = {0, 0, 1, 2};
  r.body_poses.resize(s, 28);
  for (int t = 0; t < s; ++t) {
    const double a = 0.1 * t;
    r.joints(t, 0) = a;
    const Eigen::Matrix<double, 7, 1> hand(0.3 + 0.02 * t, 0, 0.3, 1, 0, 0, 0);
    r.palm_world.row(t) = hand.transpose();
    r.palm_object.row(t) = hand.transpose();
    r.body_poses.row(t) << 0, 0, 0, 1, 0, 0, 0, 0, 0, 0.3, std::cos(a / 2), 0, 0, std::sin(a / 2),
        hand.transpose(), 0.5, 0, -0.02, 1, 0, 0, 0;
  }
  const MapObject cube = cubeObject(0.04);
  r.object_name = "cube";
  r.object_pose.position = Eigen::Vector3d(0.55, 0, 0.04);
  r.object_vertices = cube.vertices;
  r.object_faces = cube.faces;
  r.map_path = "cube.h5";
  r.map_sha256 = std::string(64, 'a');
  r.cost_terms = {"total", "path_length"};
  r.cost_history.resize(3, 2);
  r.cost_history << 3, 1, 2, 0.8, 1.5, 0.7;
  r.proximity_over_movement = Eigen::VectorXd::LinSpaced(s, 1, 0);
  r.quality_over_movement = Eigen::VectorXd::LinSpaced(s, 0, -1);
  TrajectoryShape arm;
  arm.body = 1;
  arm.axes = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  arm.center = Eigen::Vector3d(0.15, 0, 0);
  arm.half_u = 0.15;
  arm.radius = 0.04;
  TrajectoryShape palm{2,
                       TrajectoryShapeType::kCapsule,
                       Eigen::Vector3d::Zero(),
                       Eigen::Matrix3d::Identity(),
                       0.02,
                       0,
                       0.03};
  TrajectoryShape table{3,
                        TrajectoryShapeType::kSweptRectangle,
                        Eigen::Vector3d::Zero(),
                        Eigen::Matrix3d::Identity(),
                        0.3,
                        0.4,
                        0.01};
  r.shapes = {arm, palm, table};
  return r;
}

/// The JSON of the page's <script type="application/json" id="tm-data"> block.
inline nlohmann::json pageData(const std::string& html) {
  const std::string open = "id=\"tm-data\">";
  const std::size_t a = html.find(open);
  if (a == std::string::npos) return nullptr;
  const std::size_t b = html.find("</script>", a);
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

/// Path of the chromium binary, "" when none is installed.
inline std::string chromiumPath() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome"})
    if (::access(p, X_OK) == 0) return p;
  return "";
}

/// Runs headless Chromium offline on a file:// URL with a fresh profile; `action` is
/// "--dump-dom" or "--screenshot=<png> --window-size=W,H". Killed after 90 s.
inline CliRun runChromium(const std::string& url, const std::string& action,
                          const std::string& profile) {
  std::filesystem::remove_all(profile);
  std::filesystem::create_directories(profile);
  const std::string cmd =
      "{ timeout -k 5 90 " + chromiumPath() +
      " --headless --no-sandbox --use-gl=swiftshader --enable-unsafe-swiftshader"
      " --disable-gpu-sandbox --no-first-run --disable-background-networking"
      " --disable-component-update --disable-sync --disable-extensions --mute-audio"
      " --user-data-dir=" +
      profile + " --virtual-time-budget=30000 " + action + " '" + url + "' 2>/dev/null; }";
  return runShell(cmd);
}

}  // namespace taskmap::testing
