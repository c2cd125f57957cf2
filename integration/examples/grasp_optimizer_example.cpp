// Example: what a motion optimizer does with a task map (paper 1.6.2).
// 1. Build a small map in memory (grasps around three bars of a basket handle), write it with
//    writeMap and load it back with TaskMap::load, as an application loads a built map.
// 2. Rank the clusters by end-state comfort with a toy 3-joint "arm" (IK = target position).
// 3. Gradient descent on the hand pose (world frame), one evaluate() per iteration through an
//    EvaluationSession (same results as TaskMap::evaluate, cached between nearby iterates), until
//    the hand reaches the grasp manifold of the chosen cluster.
// Exits 0 when the final pose is on the map (within one kernel width of a grasp) and the
// quality cost decreased.
#include <cmath>
#include <cstdio>
#include <string>

#include <taskmap/core/error.hpp>
#include <taskmap/core/random.hpp>
#include <taskmap/integration/criteria.hpp>
#include <taskmap/integration/evaluation_session.hpp>
#include <taskmap/integration/frames.hpp>
#include <taskmap/integration/initialisation.hpp>
#include <taskmap/integration/task_map.hpp>
#include <taskmap/mapstore/map_file.hpp>

using namespace taskmap;

namespace {

TaskMapData makeMap(std::size_t n) {
  TaskMapData m;
  m.generator = "grasp_optimizer_example";
  m.object.name = "basket handle";
  m.object.vertices.resize(0, 3);
  m.grasps.pose.resize(static_cast<Eigen::Index>(n), 7);
  m.grasps.joints.resize(static_cast<Eigen::Index>(n), 0);
  m.grasps.contact_points.resize(0, 3);
  m.grasps.contact_normals.resize(0, 3);
  m.grasps.contact_offsets.assign(n + 1, 0);
  m.grasps.contacts_available = false;
  m.grasps.volume.assign(n, 0.0);
  ClusteringResult c;
  c.clusters.resize(3);
  const Eigen::Vector3d centres[3] = {{-0.15, 0, 0.15}, {0.15, 0, 0.15}, {0, 0, 0.3}};
  const Eigen::Vector3d axes[3] = {{0, 0, 1}, {0, 0, 1}, {1, 0, 0}};
  Rng rng(42);
  for (std::size_t i = 0; i < n; ++i) {
    const int b = static_cast<int>(i % 3);
    const Eigen::Vector3d a = axes[b], u = a.unitOrthogonal(), v = a.cross(u);
    const double phi = rng.uniform(0, 2 * M_PI), t = rng.uniform(-0.1, 0.1);
    const Eigen::Vector3d radial = std::cos(phi) * u + std::sin(phi) * v;
    Eigen::Matrix3d r;
    r.col(2) = -radial;
    r.col(0) = a;
    r.col(1) = r.col(2).cross(r.col(0));
    Pose p;
    p.position = centres[b] + t * a + 0.06 * radial;
    p.orientation = Eigen::Quaterniond(r);
    m.grasps.pose.row(static_cast<Eigen::Index>(i)) = p.toVector7().transpose();
    // Better grasps in the middle of each bar.
    const double eps = 0.3 * std::exp(-t * t / (2 * 0.04 * 0.04));
    m.grasps.epsilon.push_back(eps);
    m.grasps.force_closure.push_back(eps > 0.01 ? 1 : 0);
    c.labels.push_back(b);
    ClusterSummary& s = c.clusters[static_cast<std::size_t>(b)];
    if (s.size == 0 || eps > s.best_epsilon) {
      s.best_epsilon = eps;
      s.representative = static_cast<int>(i);
    }
    ++s.size;
  }
  // A valid (chain) dendrogram so that the file is complete; real maps store the clustering's.
  c.linkage.resize(static_cast<Eigen::Index>(n - 1), 4);
  for (Eigen::Index k = 0; k < c.linkage.rows(); ++k)
    c.linkage.row(k) << (k == 0 ? 0.0 : static_cast<double>(n + k - 1)), static_cast<double>(k + 1),
        0.001 * static_cast<double>(k), static_cast<double>(k + 2);
  m.clustering = c;
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string path = argc > 1 ? argv[1] : "example_map.h5";
    writeMap(path, makeMap(1500));
    const TaskMap map = TaskMap::load(path);
    std::printf("map: %zu grasps, %d clusters, sigma_p %.4f m, sigma_r %.4f rad\n", map.size(),
                map.numClusters(), *map.options().position_sigma, *map.options().rotation_sigma);

    // The object stands on a table in front of a toy robot whose "posture" is the palm position.
    Pose object;
    object.position = Eigen::Vector3d(0.5, 0.1, 0.7);
    object.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()));
    const Eigen::Vector3d lower(0.0, -0.5, 0.5), upper(1.0, 0.5, 1.5);
    IkFunction ik = [&](const Pose& target) {
      IkSolution s;
      s.success = (target.position.array() > lower.array()).all() &&
                  (target.position.array() < upper.array()).all();
      s.q = target.position;
      if (!s.success) s.message = "outside the workspace";
      return s;
    };
    // End-state comfort (the caller's; reaching's makeComfort adds collision costs): the
    // joint-limit cost of eq. 1.8 of the toy posture.
    const ComfortFunction comfort = [&](const Eigen::VectorXd& q) {
      return 0.5 * (q - 0.5 * (lower + upper)).cwiseQuotient(upper - lower).squaredNorm();
    };
    const auto ranks = rankClusters(map, object, ik, comfort);
    for (const auto& r : ranks)
      std::printf("cluster %d: %s, comfort %.4f\n", r.cluster,
                  r.reachable ? "reachable" : "unreachable", r.comfort);
    const int cluster = ranks.front().cluster;

    // Start 5 cm and 0.3 rad away from the best cluster's representative; descend in the world
    // frame with the gradient of g_p + g_q (the chain rule to a Jacobian would go here).
    Pose hand = ranks.front().target_world;
    hand.position += Eigen::Vector3d(0.03, -0.04, 0.0);
    hand.orientation =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()) * hand.orientation);
    // g_q is a normalised density (peak 1/Z, huge for narrow kernels): weigh it so that it
    // is comparable with g_p within one kernel width.
    const double sp = *map.options().position_sigma;
    const double lambda = 0.1 * sp * sp * gaussianNormaliser(sp, *map.options().rotation_sigma);
    const Evaluation start = map.evaluate(handInObject(hand, object), cluster);
    Evaluation e = start;
    // One session for the run: the iterates move little, so most calls are answered from its
    // cache (the same results as map.evaluate).
    EvaluationSession session(map, cluster);
    for (int it = 0; it < 200; ++it) {
      e = session.evaluate(handInObject(hand, object));
      const Twist g =
          handGradientToWorld(e.proximity.gradient + lambda * e.quality.gradient, object);
      // Scaled steps: linear in metres, angular in radians (W_map's units).
      const double step = 0.2;
      hand.position -= step * g.head<3>();
      hand.orientation = Eigen::Quaterniond(
          rotationExp(-step / (map.rotationScale() * map.rotationScale()) * g.tail<3>()) *
          hand.orientation.toRotationMatrix());
      if (it % 40 == 0)
        std::printf("iteration %3d: proximity %.3e, quality %.4e, nearest %zu at %.4f m\n", it,
                    e.proximity.value, e.quality.value, e.proximity.nearest.index,
                    e.proximity.nearest.distance);
    }
    std::printf("final: proximity %.3e (start %.3e), quality %.4e (start %.4e)\n",
                e.proximity.value, start.proximity.value, e.quality.value, start.quality.value);
    std::printf("session: %zu calls, %zu index searches\n", session.stats().calls,
                session.stats().anchors);
    const bool ok = e.proximity.nearest.distance < sp && e.quality.value < start.quality.value;
    return ok ? 0 : 1;
  } catch (const Error& err) {
    std::fprintf(stderr, "grasp_optimizer_example: %s\n", err.what());
    return 1;
  }
}
