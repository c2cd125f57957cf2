// The pictures of a grasp plan (`taskmap reach --map --png`): snapshots and cost curves
// (reach_picture.hpp).
#include <string>
#include <vector>

#include "taskmap/picture/cost_picture.hpp"
#include "taskmap/picture/reach_picture.hpp"
#include "taskmap/reaching/kinematics.hpp"

namespace taskmap {
namespace {

void drawCosts(const ClusterPlan& b, const MovementTerms& movement, double dt,
               const std::string& path) {
  std::vector<double> total, length, velocity, collision, limit;
  for (const TrajectoryCost& t : b.optimization.history) {
    total.push_back(t.total);
    length.push_back(t.path_length);
    velocity.push_back(t.end_velocity);
    collision.push_back(t.collision);
    limit.push_back(t.joint_limit);
  }
  writeCostPicture(
      {{"trajectory cost terms per iteration",
        "iteration",
        1.0,
        {{"total", total},
         {"path length", length},
         {"end velocity", velocity},
         {"collision", collision},
         {"joint limit", limit}}},
       {"task map terms per iteration",
        "iteration",
        1.0,
        {{"proximity g_p", b.proximity}, {"quality g_q", b.quality}}},
       {"proximity over the final movement",
        "time [s]",
        dt,
        {{"proximity g_p", movement.proximity}}},
       {"quality over the final movement", "time [s]", dt, {{"quality g_q", movement.quality}}}},
      path);
}

}  // namespace

std::string costPicturePath(const std::string& png) {
  const std::string::size_type dot = png.rfind(".png");
  return (dot != std::string::npos && dot + 4 == png.size() ? png.substr(0, dot) : png) +
         "_costs.png";
}

void writeGraspPlanPictures(const RobotModel& robot, const ClusterPlan& b,
                            const MovementTerms& movement, int palm,
                            const Eigen::Isometry3d& grasp_world, double dt,
                            const std::string& png) {
  ReachResult r;
  r.q = b.optimization.cost.q;
  Kinematics kin(robot);
  for (const Eigen::VectorXd& q : r.q) {
    kin.update(q);
    r.palm.push_back(kin.pose(palm));
  }
  const int n = static_cast<int>(r.q.size()) - 1;
  writeReachPicture(robot, r, palm, {0, n / 3, 2 * n / 3, n}, grasp_world, png);
  drawCosts(b, movement, dt, costPicturePath(png));
}

}  // namespace taskmap
