#include "taskmap/integration/initialisation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "taskmap/core/error.hpp"

namespace taskmap {
void RankOptions::validate() const {
  if (member_tries < 0)
    throw Error("rank options: member_tries must be >= 0 (0 = the representative only)");
}

namespace {

/// Entries at `tries` evenly spaced ranks of `items` (all of them when there are fewer).
std::vector<std::size_t> spread(const std::vector<std::size_t>& items, int tries) {
  const std::size_t n = items.size(), k = std::min(n, static_cast<std::size_t>(tries));
  std::vector<std::size_t> out;
  for (std::size_t j = 0; j < k; ++j) out.push_back(items[k == 1 ? 0 : j * (n - 1) / (k - 1)]);
  return out;
}

/// The members of cluster c other than its representative, in the order they are tried:
/// sorted by pose distance to the representative, farthest first, then `tries` of them at
/// evenly spaced ranks (the farthest and, with two tries or more, the nearest included).
std::vector<std::size_t> membersToTry(const TaskMap& map, int c, std::size_t representative,
                                      int tries) {
  std::vector<std::pair<double, std::size_t>> by_distance;
  const std::vector<int>& labels = map.data().clustering->labels;
  const Pose rep = map.pose(representative);
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (labels[i] == c && i != representative)
      by_distance.emplace_back(poseDistanceSquared(map.pose(i), rep, map.rotationScale()), i);
  std::sort(by_distance.begin(), by_distance.end(),
            [](const auto& a, const auto& b) { return a.first > b.first; });  // farthest first
  std::vector<std::size_t> members;
  for (const auto& m : by_distance) members.push_back(m.second);
  return spread(members, tries);
}

/// A pose given in the object frame, in the world frame.
Pose inWorld(const Pose& object_world, const Pose& in_object) {
  const Eigen::Quaterniond qo = object_world.orientation.normalized();
  Pose p;
  p.position = object_world.position + qo * in_object.position;
  p.orientation = (qo * in_object.orientation).normalized();
  return p;
}

/// Makes grasp the rank's target: its palm pose in the object and in the world frame.
void setTarget(const TaskMap& map, const Pose& object_world, std::size_t grasp, ClusterRank& r) {
  r.target = grasp;
  r.target_object = map.pose(grasp);
  r.target_world = inWorld(object_world, r.target_object);
}

/// IK and comfort of one grasp; when reachable with a finite comfort, the grasp becomes the
/// rank's target (posture and comfort with it) and true is returned. A failure leaves the
/// target as it was and keeps the first failure's message.
bool tryTarget(const TaskMap& map, const Pose& object_world, std::size_t grasp,
               const IkFunction& ik, const ComfortFunction& comfort, ClusterRank& r) {
  ++r.tried;
  const IkSolution s = ik(inWorld(object_world, map.pose(grasp)));
  if (!s.success) {
    if (r.message.empty()) r.message = s.message.empty() ? "inverse kinematics failed" : s.message;
    return false;
  }
  const double c_value = comfort(s.q);
  if (!std::isfinite(c_value)) {
    if (r.message.empty()) r.message = "comfort cost is not finite";
    return false;
  }
  setTarget(map, object_world, grasp, r);
  r.q = s.q;
  r.reachable = true;
  r.comfort = c_value;
  r.message.clear();
  return true;
}

/// The outliers (grasps in no cluster) as a last resort, cluster -1: at most `tries` of them
/// (in index order, evenly spread), the first reachable one the target.
ClusterRank rankOutliers(const TaskMap& map, const Pose& object_world, const IkFunction& ik,
                         const ComfortFunction& comfort, int tries) {
  std::vector<std::size_t> outliers;
  const std::vector<int>& labels = map.data().clustering->labels;
  for (std::size_t i = 0; i < labels.size(); ++i)
    if (labels[i] < 0) outliers.push_back(i);
  ClusterRank r;
  r.cluster = -1;
  r.comfort = std::numeric_limits<double>::infinity();
  for (std::size_t o : spread(outliers, tries))
    if (tryTarget(map, object_world, o, ik, comfort, r)) {
      r.representative = o;
      break;
    }
  return r;
}

}  // namespace

std::vector<ClusterRank> rankClusters(const TaskMap& map, const Pose& object_world,
                                      const IkFunction& ik, const ComfortFunction& comfort,
                                      const RankOptions& options) {
  if (!ik) throw Error("rankClusters: no inverse kinematics function given");
  if (!comfort) throw Error("rankClusters: no comfort function given");
  if (!map.data().clustering || map.numClusters() == 0)
    throw Error("rankClusters: the map has no clusters; cluster the map first");
  options.validate();
  const auto reachable = [](const ClusterRank& r) { return r.reachable; };
  std::vector<ClusterRank> out;
  for (int c = 0; c < map.numClusters(); ++c) {
    ClusterRank r;
    r.cluster = c;
    r.representative = static_cast<std::size_t>(
        map.data().clustering->clusters[static_cast<std::size_t>(c)].representative);
    r.comfort = std::numeric_limits<double>::infinity();
    setTarget(map, object_world, r.representative, r);  // kept when nothing is reachable
    if (!options.members_only) tryTarget(map, object_world, r.representative, ik, comfort, r);
    out.push_back(std::move(r));
  }
  // Fallbacks, when no representative is reachable (or none was tried): members, then the
  // outliers (with members_only, the outliers in any case).
  if (options.member_tries > 0 && std::none_of(out.begin(), out.end(), reachable)) {
    for (ClusterRank& r : out)
      for (std::size_t m : membersToTry(map, r.cluster, r.representative, options.member_tries))
        if (tryTarget(map, object_world, m, ik, comfort, r)) break;
    if (options.members_only || std::none_of(out.begin(), out.end(), reachable)) {
      ClusterRank r = rankOutliers(map, object_world, ik, comfort, options.member_tries);
      if (r.reachable) out.push_back(std::move(r));
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const ClusterRank& a, const ClusterRank& b) {
    if (a.reachable != b.reachable) return a.reachable;
    if (a.reachable && a.comfort != b.comfort) return a.comfort < b.comfort;
    return a.cluster < b.cluster;
  });
  return out;
}

}  // namespace taskmap
