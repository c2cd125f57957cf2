// Attractor dynamics eq. 1.17-1.19 and the reaching rollout (attractor + IK at each step).
#include "taskmap/reaching/attractor.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "taskmap/core/error.hpp"
#include "taskmap/core/pose.hpp"

namespace taskmap {

void AttractorOptions::validate() const {
  const auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw Error(std::string("attractor options: ") + name + " must be finite and > 0");
  };
  positive(relaxation_time, "relaxation_time (seconds)");
  positive(damping, "damping");
  positive(dt, "dt (seconds)");
}

AttractorCoefficients attractorCoefficients(const AttractorOptions& o) {
  o.validate();
  const double t2 = o.relaxation_time * o.relaxation_time, dt2 = o.dt * o.dt;
  const double denom = t2 + 2.0 * o.relaxation_time * o.damping * o.dt + dt2;
  return {dt2 / denom, t2 / denom};
}

Eigen::VectorXd attractorStep(const AttractorCoefficients& c, const Eigen::VectorXd& x,
                              const Eigen::VectorXd& x_previous, const Eigen::VectorXd& r_next) {
  return x + c.a * (r_next - x) + c.b * (x - x_previous);
}

Eigen::VectorXd attractorPoint(const Eigen::VectorXd& x0,
                               const std::vector<Eigen::VectorXd>& points, double segment_time,
                               double t) {
  assert(!points.empty() && segment_time > 0.0);
  const double s = std::max(0.0, t) / segment_time;
  const int k = static_cast<int>(std::floor(s));
  if (k >= static_cast<int>(points.size())) return points.back();
  const Eigen::VectorXd& from = k == 0 ? x0 : points[k - 1];
  return from + (s - k) * (points[k] - from);
}

std::vector<Eigen::VectorXd> attractorTrajectory(const AttractorOptions& options,
                                                 const Eigen::VectorXd& x0,
                                                 const std::vector<Eigen::VectorXd>& points,
                                                 double segment_time, int steps) {
  const AttractorCoefficients c = attractorCoefficients(options);
  if (points.empty()) throw Error("attractor trajectory: give at least one attractor point");
  for (const auto& p : points)
    if (p.size() != x0.size() || !p.allFinite())
      throw Error("attractor trajectory: every point needs " + std::to_string(x0.size()) +
                  " finite values");
  if (!(segment_time > 0.0) || steps < 1)
    throw Error("attractor trajectory: segment_time must be > 0 s and steps >= 1");
  std::vector<Eigen::VectorXd> x{x0};
  Eigen::VectorXd previous = x0;
  for (int t = 0; t < steps; ++t) {
    const Eigen::VectorXd next = attractorStep(
        c, x.back(), previous, attractorPoint(x0, points, segment_time, (t + 1) * options.dt));
    previous = x.back();
    x.push_back(next);
  }
  return x;
}

void ReachOptions::validate() const {
  attractor.validate();
  if (steps < 1) throw Error("reach options: steps must be >= 1");
  if (!(move_time > 0.0) || !std::isfinite(move_time))
    throw Error("reach options: move_time must be > 0 seconds");
  if (!(position_tolerance > 0.0) || !(orientation_tolerance > 0.0))
    throw Error("reach options: tolerances must be > 0");
}

Eigen::Matrix<double, 6, 1> taskVariables(const Eigen::Isometry3d& pose,
                                          const Eigen::Matrix3d& target) {
  Eigen::Matrix<double, 6, 1> x;
  x.head<3>() = pose.translation();
  x.tail<3>() = rotationLog(target.transpose() * pose.linear());
  return x;
}

Eigen::Isometry3d goalPose(const Eigen::VectorXd& x, const Eigen::Matrix3d& target) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = x.head<3>();
  t.linear() = target * rotationExp(x.tail<3>());
  return t;
}

Eigen::VectorXd reachStep(const ResolvedRateIK& ik, const Kinematics& kin,
                          const Eigen::Matrix3d& frame, double dt, const Eigen::VectorXd& x,
                          const Eigen::VectorXd& x_next, IkStepTrace* trace) {
  const Eigen::Isometry3d goal = goalPose(x_next, frame);
  const Eigen::Isometry3d now = goalPose(x, frame);
  std::vector<TaskGoal> goals(2);
  goals[0].position = now.translation();  // feedback on the current desired pose
  goals[0].velocity = (goal.translation() - now.translation()) / dt;
  goals[1].rotation = now.linear();
  goals[1].velocity = rotationLog(goal.linear() * now.linear().transpose()) / dt;
  return ik.step(kin, goals, dt, nullptr, trace);
}

namespace {

Eigen::Isometry3d relativePose(const Kinematics& kin, int body, int reference) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = kin.relativePosition(body, reference);
  t.linear() = kin.relativeRotation(body, reference);
  return t;
}

void trackClearance(const CollisionModel* collisions, const Kinematics& kin, int step,
                    ReachResult& r) {
  if (!collisions || collisions->pairs().empty()) return;
  int pair = -1;
  const double d = collisions->minimumDistance(kin, &pair);
  if (d < r.min_clearance) {
    r.min_clearance = d;
    r.min_clearance_pair = collisions->pairName(pair);
    r.min_clearance_step = step;
  }
}

void summarize(const ReachOptions& options, const Eigen::Isometry3d& target, ReachResult& r) {
  const Eigen::Isometry3d& last = r.palm.back();
  r.position_error = (target.translation() - last.translation()).norm();
  r.orientation_error = rotationLog(target.linear() * last.linear().transpose()).norm();
  const bool reached = r.position_error < options.position_tolerance &&
                       r.orientation_error < options.orientation_tolerance;
  r.status = r.min_clearance < 0.0 ? ReachStatus::kCollided
             : reached             ? ReachStatus::kReached
                                   : ReachStatus::kNotReached;
  r.message = r.status == ReachStatus::kReached ? "reached the target"
              : r.status == ReachStatus::kCollided
                  ? "penetrated " + r.min_clearance_pair + " at step " +
                        std::to_string(r.min_clearance_step)
                  : "target not reached within " + std::to_string(options.steps) + " steps";
}

}  // namespace

ReachResult reach(const RobotModel& robot, const CollisionModel* collisions, int body,
                  int reference, const Eigen::Isometry3d& target, const Eigen::VectorXd& q0,
                  const ReachOptions& options) {
  options.validate();
  if (q0.size() != robot.dofs() || !q0.allFinite())
    throw Error("reach: start configuration needs " + std::to_string(robot.dofs()) +
                " finite values");
  if ((q0 - robot.lower()).minCoeff() < 0.0 || (robot.upper() - q0).minCoeff() < 0.0)
    throw Error("reach: start configuration is outside the joint limits");
  if (!target.matrix().allFinite()) throw Error("reach: target pose is not finite");
  for (const Eigen::Isometry3d& via : options.via_points)
    if (!via.matrix().allFinite()) throw Error("reach: a via point is not finite");
  const ResolvedRateIK ik(
      robot,
      {{TaskKind::kPosition, body, reference, -1}, {TaskKind::kOrientation, body, reference, -1}},
      collisions, options.ik);
  const AttractorCoefficients c = attractorCoefficients(options.attractor);
  const double dt = options.attractor.dt;
  Kinematics kin(robot);
  kin.update(q0);
  ReachResult r;
  r.q.push_back(q0);
  r.palm.push_back(relativePose(kin, body, reference));
  r.min_clearance = std::numeric_limits<double>::infinity();
  r.joint_limit_margin = jointLimitMargin(robot, q0);
  trackClearance(collisions, kin, 0, r);
  const Eigen::VectorXd x0 = taskVariables(r.palm.back(), target.linear());
  std::vector<Eigen::VectorXd> points;
  for (const Eigen::Isometry3d& via : options.via_points)
    points.push_back(taskVariables(via, target.linear()));
  points.push_back(taskVariables(target, target.linear()));
  const double segment_time = options.move_time / static_cast<double>(points.size());
  Eigen::VectorXd x = x0, x_previous = x0;
  for (int t = 0; t < options.steps; ++t) {
    const Eigen::VectorXd x_next =
        attractorStep(c, x, x_previous, attractorPoint(x0, points, segment_time, (t + 1) * dt));
    const Eigen::VectorXd q = reachStep(ik, kin, target.linear(), dt, x, x_next);
    kin.update(q);
    x_previous = x;
    x = x_next;
    r.q.push_back(q);
    r.palm.push_back(relativePose(kin, body, reference));
    r.joint_limit_margin = std::min(r.joint_limit_margin, jointLimitMargin(robot, q));
    trackClearance(collisions, kin, t + 1, r);
  }
  summarize(options, target, r);
  return r;
}

}  // namespace taskmap
