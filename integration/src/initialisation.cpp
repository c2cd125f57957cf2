#include "taskmap/integration/initialisation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "taskmap/core/error.hpp"

namespace taskmap {
std::vector<ClusterRank> rankClusters(const TaskMap& map, const Pose& object_world,
                                      const IkFunction& ik, const ComfortFunction& comfort) {
  if (!ik) throw Error("rankClusters: no inverse kinematics function given");
  if (!comfort) throw Error("rankClusters: no comfort function given");
  if (!map.data().clustering || map.numClusters() == 0)
    throw Error("rankClusters: the map has no clusters; cluster the map first");
  const Eigen::Quaterniond qo = object_world.orientation.normalized();
  std::vector<ClusterRank> out;
  for (int c = 0; c < map.numClusters(); ++c) {
    ClusterRank r;
    r.cluster = c;
    r.representative = static_cast<std::size_t>(
        map.data().clustering->clusters[static_cast<std::size_t>(c)].representative);
    r.target_object = map.pose(r.representative);
    r.target_world.position = object_world.position + qo * r.target_object.position;
    r.target_world.orientation = (qo * r.target_object.orientation).normalized();
    const IkSolution s = ik(r.target_world);
    r.comfort = std::numeric_limits<double>::infinity();
    if (s.success) {
      r.q = s.q;
      const double c_value = comfort(s.q);
      if (std::isfinite(c_value)) {
        r.reachable = true;
        r.comfort = c_value;
      } else {
        r.message = "comfort cost is not finite";
      }
    } else {
      r.message = s.message.empty() ? "inverse kinematics failed" : s.message;
    }
    out.push_back(std::move(r));
  }
  std::stable_sort(out.begin(), out.end(), [](const ClusterRank& a, const ClusterRank& b) {
    if (a.reachable != b.reachable) return a.reachable;
    if (a.reachable && a.comfort != b.comfort) return a.comfort < b.comfort;
    return a.cluster < b.cluster;
  });
  return out;
}

}  // namespace taskmap
