// Collision cost eq. 1.9-1.16 over the selected primitive pairs.
#include "taskmap/reaching/collision_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "taskmap/core/error.hpp"
#include "taskmap/reaching/robot_costs.hpp"

namespace taskmap {
namespace {

/// Number of moving joints on the tree path between bodies a and b.
int jointGap(const RobotModel& robot, int a, int b) {
  const auto& bodies = robot.bodies();
  int gap = 0;
  while (a != b) {
    // Step up from the deeper body (by index: parents come first).
    int& deeper = a > b ? a : b;
    if (bodies[deeper].joint != JointType::kFixed) ++gap;
    deeper = bodies[deeper].parent;
  }
  return gap;
}

Eigen::Vector3d worldCenter(const Kinematics& kin, int body, const Primitive& p) {
  return kin.pose(body) * p.center;
}

}  // namespace

void CollisionOptions::validate() const {
  if (!(boundary_distance > 0.0) || !std::isfinite(boundary_distance))
    throw Error("collision options: boundary_distance must be > 0 metres (e.g. 0.05)");
  if (!(slope > 0.0) || !std::isfinite(slope))
    throw Error("collision options: slope must be > 0 (e.g. 1)");
  if (!std::isfinite(center_weight))
    throw Error("collision options: center_weight must be finite (negative: automatic)");
  if (min_environment_depth < 0)
    throw Error("collision options: min_environment_depth must be >= 0");
  if (min_self_gap < 1) throw Error("collision options: min_self_gap must be >= 1");
}

CollisionModel::CollisionModel(const RobotModel& robot, const CollisionOptions& options)
    : robot_(&robot), options_(options) {
  options.validate();
  center_weight_ = options.center_weight < 0.0
                       ? options.slope * options.boundary_distance * options.boundary_distance
                       : options.center_weight;
  for (const std::string& name : options.hand_may_touch) robot.requireBody(name);
  const auto& bodies = robot.bodies();
  Kinematics mid(robot);
  const auto add = [&](int a, int b, bool self) {
    for (size_t sa = 0; sa < bodies[a].shapes.size(); ++sa) {
      for (size_t sb = 0; sb < bodies[b].shapes.size(); ++sb) {
        const CollisionPair p{a, static_cast<int>(sa), b, static_cast<int>(sb)};
        if (self &&
            primitiveDistance(bodies[a].shapes[sa], mid.pose(a), bodies[b].shapes[sb], mid.pose(b))
                    .distance <= 0.0)
          continue;  // overlapping by construction
        pairs_.push_back(p);
      }
    }
  };
  for (int a = 0; a < static_cast<int>(bodies.size()); ++a) {
    if (bodies[a].role == BodyRole::kEnvironment || bodies[a].shapes.empty()) continue;
    for (int b = 0; b < static_cast<int>(bodies.size()); ++b) {
      if (b == a || bodies[b].shapes.empty()) continue;
      if (bodies[b].role == BodyRole::kEnvironment) {
        if (bodies[a].chain_depth < options.min_environment_depth) continue;
        const auto& touch = options.hand_may_touch;
        if (bodies[a].role == BodyRole::kHand &&
            std::find(touch.begin(), touch.end(), bodies[b].name) != touch.end())
          continue;
        add(a, b, false);
      } else if (options.self_collision && b > a && jointGap(robot, a, b) >= options.min_self_gap) {
        add(a, b, true);
      }
    }
  }
}

std::string CollisionModel::pairName(int pair) const {
  const CollisionPair& p = pairs_.at(pair);
  const auto& bodies = robot_->bodies();
  return bodies[p.body_a].name + "[" + std::to_string(p.shape_a) + "] - " + bodies[p.body_b].name +
         "[" + std::to_string(p.shape_b) + "]";
}

std::vector<PairDistance> CollisionModel::distances(const Kinematics& kin) const {
  std::vector<PairDistance> out(pairs_.size());
  const auto& bodies = robot_->bodies();
  for (size_t i = 0; i < pairs_.size(); ++i) {
    const CollisionPair& p = pairs_[i];
    const Primitive& a = bodies[p.body_a].shapes[p.shape_a];
    const Primitive& b = bodies[p.body_b].shapes[p.shape_b];
    out[i].closest = primitiveDistance(a, kin.pose(p.body_a), b, kin.pose(p.body_b));
    out[i].center_distance = (worldCenter(kin, p.body_b, b) - worldCenter(kin, p.body_a, a)).norm();
  }
  return out;
}

double CollisionModel::minimumDistance(const Kinematics& kin, int* pair) const {
  double best = std::numeric_limits<double>::infinity();
  const std::vector<PairDistance> d = distances(kin);
  for (size_t i = 0; i < d.size(); ++i) {
    if (d[i].closest.distance < best) {
      best = d[i].closest.distance;
      if (pair) *pair = static_cast<int>(i);
    }
  }
  return best;
}

double CollisionModel::closestPointCost(double d, double* derivative) const {
  return collisionPairCost(d, options_.boundary_distance, options_.slope, derivative);
}

double CollisionModel::centerPointCost(double dp, double dc, double* d_dp, double* d_dc) const {
  const double db = options_.boundary_distance;
  const double e = center_weight_ * std::exp(-dc);
  double scale = 0.0, dscale = 0.0;  // (1 - d_p / d_B) in the parabolic zone
  if (dp < 0.0) {
    scale = 1.0;
  } else if (dp < db) {
    scale = 1.0 - dp / db;
    dscale = -1.0 / db;
  }
  if (d_dp) *d_dp = dscale * e;
  if (d_dc) *d_dc = -scale * e;
  return scale * e;
}

double CollisionModel::cost(const Kinematics& kin, Eigen::VectorXd* gradient) const {
  if (gradient) gradient->setZero(robot_->dofs());
  const auto& bodies = robot_->bodies();
  const double db = options_.boundary_distance;
  double h = 0.0;
  for (const CollisionPair& p : pairs_) {
    const Primitive& a = bodies[p.body_a].shapes[p.shape_a];
    const Primitive& b = bodies[p.body_b].shapes[p.shape_b];
    const Eigen::Vector3d ca = worldCenter(kin, p.body_a, a), cb = worldCenter(kin, p.body_b, b);
    const double dc = (cb - ca).norm();
    if (dc - a.boundingRadius() - b.boundingRadius() >= db) continue;  // all terms zero
    const PrimitiveDistance d = primitiveDistance(a, kin.pose(p.body_a), b, kin.pose(p.body_b));
    double gp_d = 0.0, gc_dp = 0.0, gc_dc = 0.0;
    h += closestPointCost(d.distance, &gp_d) + centerPointCost(d.distance, dc, &gc_dp, &gc_dc);
    if (!gradient) continue;
    // Eq. 1.12: dd_p/dq = n^T (J_{p_b} - J_{p_a}), n the unit direction from a to b.
    const double k = gp_d + gc_dp;
    if (k != 0.0) {
      kin.addJacobianTransposeTimes(p.body_b, d.core_b, k * d.normal, *gradient);
      kin.addJacobianTransposeTimes(p.body_a, d.core_a, -k * d.normal, *gradient);
    }
    // Eq. 1.14: the centre distance term, zero where the centres coincide.
    if (gc_dc != 0.0 && dc > 1e-12) {
      const Eigen::Vector3d m = (cb - ca) / dc;
      kin.addJacobianTransposeTimes(p.body_b, cb, gc_dc * m, *gradient);
      kin.addJacobianTransposeTimes(p.body_a, ca, -gc_dc * m, *gradient);
    }
  }
  return h;
}

}  // namespace taskmap
