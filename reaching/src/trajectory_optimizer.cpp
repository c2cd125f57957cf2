// Trajectory optimisation over attractor points (paper section 1.5, docs/REACHING.md
// "Trajectory optimisation", T1-T4): forward rollout, cost terms, backward (adjoint) pass through
// the IK steps and the attractor.
#include "taskmap/reaching/trajectory_optimizer.hpp"

#include <cassert>
#include <cmath>
#include <limits>

#include "descent_record.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/reaching/ik_step_derivative.hpp"

namespace taskmap {

void TrajectoryCostWeights::validate() const {
  const auto check = [](double v, const char* name) {
    if (!(v >= 0.0) || !std::isfinite(v))
      throw Error(std::string("trajectory cost weights: ") + name + " must be finite and >= 0");
  };
  check(path_length, "path_length");
  check(end_velocity, "end_velocity");
  check(collision, "collision");
  check(joint_limit, "joint_limit");
}

void TrajectoryProblem::validate() const {
  if (!robot) throw Error("trajectory problem: give a robot model");
  reach.validate();
  reach.ik.validate(robot->dofs());
  weights.validate();
  if (body < 0 || body >= static_cast<int>(robot->bodies().size()) || reference < -1 ||
      reference >= static_cast<int>(robot->bodies().size()))
    throw Error("trajectory problem: body or reference is not a body of the robot");
  if (q0.size() != robot->dofs() || !q0.allFinite())
    throw Error("trajectory problem: q0 needs " + std::to_string(robot->dofs()) + " finite values");
  if ((q0 - robot->lower()).minCoeff() < 0.0 || (robot->upper() - q0).minCoeff() < 0.0)
    throw Error("trajectory problem: q0 is outside the joint limits");
  if (!(step_jacobian_epsilon > 0.0) || step_jacobian_epsilon > 1e-2)
    throw Error("trajectory problem: step_jacobian_epsilon must be in (0, 1e-2]");
  if (step_derivative == StepDerivative::kAnalytic && reference >= 0 &&
      !robot->bodyDofs()[reference].empty())
    throw Error(
        "trajectory problem: the analytic step derivative needs a reference body no "
        "joint moves; use StepDerivative::kFiniteDifferences");
}

void TrajectoryOptimizerOptions::validate() const {
  if (max_iterations < 1) throw Error("trajectory optimizer: max_iterations must be >= 1");
  if (!(initial_step > 0.0) || !std::isfinite(initial_step))
    throw Error("trajectory optimizer: initial_step must be > 0");
  if (!(relative_tolerance >= 0.0)) throw Error("trajectory optimizer: relative_tolerance >= 0");
}

Eigen::Matrix<double, 6, 1> startTaskVariables(const TrajectoryProblem& problem) {
  Kinematics kin(*problem.robot);
  kin.update(problem.q0);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = kin.relativePosition(problem.body, problem.reference);
  pose.linear() = kin.relativeRotation(problem.body, problem.reference);
  return taskVariables(pose, problem.frame);
}

namespace {

/// Weights of the linear attractor: x_t = W(t,0) x0 + sum_k W(t,k+1) p_k (eq. 1.17-1.18 are
/// linear and act on every component alike), found by running them on unit vectors.
std::vector<Eigen::VectorXd> attractorWeights(const TrajectoryProblem& p, int points) {
  std::vector<Eigen::VectorXd> unit(points, Eigen::VectorXd::Zero(points + 1));
  for (int k = 0; k < points; ++k) unit[k][k + 1] = 1.0;
  return attractorTrajectory(p.reach.attractor, Eigen::VectorXd::Unit(points + 1, 0), unit,
                             p.reach.move_time / points, p.reach.steps);
}

/// Running cost dt (w_c H_coll + w_jl H_jl) at q given H_coll(q) and (with grad) dH_coll/dq.
void addStateCost(const TrajectoryProblem& p, const Eigen::VectorXd& q, double h_coll,
                  const Eigen::VectorXd& h_coll_gradient, TrajectoryCost& c,
                  Eigen::VectorXd* grad) {
  const double dt = p.reach.attractor.dt;
  if (p.collisions && p.weights.collision > 0.0) {
    c.collision += dt * p.weights.collision * h_coll;
    if (grad && h_coll_gradient.size() > 0) *grad += dt * p.weights.collision * h_coll_gradient;
  }
  if (p.weights.joint_limit > 0.0) {
    Eigen::VectorXd g;
    c.joint_limit += dt * p.weights.joint_limit * jointLimitCost(*p.robot, q, grad ? &g : nullptr);
    if (grad) *grad += dt * p.weights.joint_limit * g;
  }
}

/// A rollout and what its backward pass needs.
struct Tape {
  std::vector<Eigen::VectorXd> x;   ///< attractor states x_0 .. x_T
  std::vector<Eigen::VectorXd> dq;  ///< direct dC/dq_t (empty without derivatives)
  std::vector<IkStepTrace> traces;  ///< the IK steps' intermediate values
};

/// Forward pass: joint trajectory, cost terms and (with derivatives) the direct dC/dq_t. The
/// collision cost of q_t (t >= 1) is the one the IK step from q_t evaluated (same state).
void forwardPass(const TrajectoryProblem& p, const ResolvedRateIK& ik, Tape& tape,
                 TrajectoryCost& c, bool derivatives) {
  const int steps = p.reach.steps, n = p.robot->dofs();
  const double dt = p.reach.attractor.dt;
  Kinematics kin(*p.robot);
  kin.update(p.q0);
  c.q.assign(1, p.q0);
  std::vector<Eigen::VectorXd>* dq = derivatives ? &tape.dq : nullptr;
  if (dq) dq->assign(steps + 1, Eigen::VectorXd::Zero(n));
  tape.traces.resize(steps);
  Eigen::Vector3d previous_position = kin.relativePosition(p.body, p.reference);
  Eigen::Matrix3Xd previous_jacobian;
  for (int t = 0; t < steps; ++t) {
    if (t == steps - 1) previous_jacobian = kin.relativePositionJacobian(p.body, p.reference);
    if (t == steps - 1) previous_position = kin.relativePosition(p.body, p.reference);
    IkStepTrace& trace = tape.traces[t];
    const Eigen::VectorXd q = reachStep(ik, kin, p.frame, dt, tape.x[t], tape.x[t + 1], &trace);
    if (t > 0)
      addStateCost(p, c.q[t], trace.collision_cost, trace.collision_gradient, c,
                   dq ? &(*dq)[t] : nullptr);
    kin.update(q);
    const Eigen::VectorXd delta = q - c.q.back();
    c.path_length += p.weights.path_length * delta.squaredNorm() / dt;
    if (dq) {
      (*dq)[t + 1] += 2.0 * p.weights.path_length * delta / dt;
      (*dq)[t] -= 2.0 * p.weights.path_length * delta / dt;
    }
    c.q.push_back(q);
  }
  Eigen::VectorXd last_gradient;
  const double last = p.collisions && p.weights.collision > 0.0
                          ? p.collisions->cost(kin, dq ? &last_gradient : nullptr)
                          : 0.0;
  addStateCost(p, c.q[steps], last, last_gradient, c, dq ? &(*dq)[steps] : nullptr);
  const Eigen::Vector3d v = (kin.relativePosition(p.body, p.reference) - previous_position) / dt;
  c.end_velocity = p.weights.end_velocity * v.squaredNorm();
  if (dq) {
    const Eigen::Vector3d f = 2.0 * p.weights.end_velocity * v / dt;
    (*dq)[steps] += kin.relativePositionJacobian(p.body, p.reference).transpose() * f;
    (*dq)[steps - 1] -= previous_jacobian.transpose() * f;
  }
  if (p.terminal) {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
    c.terminal = p.terminal(kin, dq ? &g : nullptr);
    if (dq) (*dq)[steps] += g;
  }
  c.total = c.path_length + c.end_velocity + c.collision + c.joint_limit + c.terminal;
}

/// lambda^T F for the IK step F(q, x, x_next).
double projectedStep(const ResolvedRateIK& ik, Kinematics& kin, const TrajectoryProblem& p,
                     const Eigen::VectorXd& lambda, const Eigen::VectorXd& q,
                     const Eigen::VectorXd& x, const Eigen::VectorXd& x_next) {
  kin.update(q);
  return lambda.dot(reachStep(ik, kin, p.frame, p.reach.attractor.dt, x, x_next));
}

/// Backward pass: lambda_t = dC/dq_t + (dF/dq_t)^T lambda_{t+1}, dC/dx_t accumulated from
/// (dF/dx_t)^T lambda_{t+1}; each IK step's products analytic (docs/REACHING.md T3).
std::vector<Eigen::VectorXd> analyticBackwardPass(const TrajectoryProblem& p,
                                                  const ResolvedRateIK& ik, const Tape& tape,
                                                  const TrajectoryCost& c) {
  const std::vector<Eigen::VectorXd>& x = tape.x;
  const std::vector<Eigen::VectorXd>& dq = tape.dq;
  const std::vector<IkStepTrace>& traces = tape.traces;
  const int steps = p.reach.steps;
  ReachStepDerivative derivative(ik, p.frame, p.reach.attractor.dt, p.step_jacobian_epsilon);
  Kinematics kin(*p.robot);
  std::vector<Eigen::VectorXd> dx(steps + 1, Eigen::VectorXd::Zero(6));
  Eigen::VectorXd lambda = dq[steps];
  for (int t = steps - 1; t >= 0; --t) {
    kin.update(c.q[t]);
    const ReachStepAdjoint a = derivative.vectorJacobian(kin, x[t], x[t + 1], traces[t], lambda);
    dx[t] += a.x;
    dx[t + 1] += a.x_next;
    lambda = dq[t] + a.q;
  }
  return dx;
}

/// The same products by finite differences of lambda^T F (the oracle, docs/REACHING.md T3).
std::vector<Eigen::VectorXd> backwardPass(const TrajectoryProblem& p, const ResolvedRateIK& ik,
                                          const std::vector<Eigen::VectorXd>& x,
                                          const TrajectoryCost& c,
                                          const std::vector<Eigen::VectorXd>& dq) {
  const int steps = p.reach.steps, n = p.robot->dofs();
  const double h = p.step_jacobian_epsilon;
  Kinematics kin(*p.robot);
  std::vector<Eigen::VectorXd> dx(steps + 1, Eigen::VectorXd::Zero(6));
  Eigen::VectorXd lambda = dq[steps];
  const bool central = p.step_jacobian_differences == FiniteDifferences::kCentral;
  for (int t = steps - 1; t >= 0; --t) {
    // lambda^T F at the inputs (q, x_t, x_{t+1}) shifted along one coordinate by +-h.
    const auto shifted = [&](int input, double shift) {
      Eigen::VectorXd q = c.q[t], a = x[t], b = x[t + 1];
      if (input < 6)
        a[input] += shift;
      else if (input < 12)
        b[input - 6] += shift;
      else
        q[input - 12] += shift;
      return projectedStep(ik, kin, p, lambda, q, a, b);
    };
    const double base = central ? 0.0 : shifted(0, 0.0);
    const auto derivative = [&](int input) {
      return central ? (shifted(input, h) - shifted(input, -h)) / (2.0 * h)
                     : (shifted(input, h) - base) / h;
    };
    for (int i = 0; i < 6; ++i) {
      dx[t][i] += derivative(i);
      dx[t + 1][i] += derivative(6 + i);
    }
    if (t == 0) break;
    Eigen::VectorXd next = dq[t];
    for (int i = 0; i < n; ++i) next[i] += derivative(12 + i);
    lambda = next;
  }
  return dx;
}

}  // namespace

namespace {

ResolvedRateIK trajectoryIk(const TrajectoryProblem& problem) {
  return ResolvedRateIK(*problem.robot,
                        {{TaskKind::kPosition, problem.body, problem.reference, -1},
                         {TaskKind::kOrientation, problem.body, problem.reference, -1}},
                        problem.collisions, problem.reach.ik);
}

/// Validated problem and points: the rollout with its tape (derivatives: the direct dC/dq_t).
TrajectoryCost rollOut(const TrajectoryProblem& problem, const ResolvedRateIK& ik,
                       const std::vector<Eigen::VectorXd>& points, bool derivatives, Tape& tape) {
  const int k = static_cast<int>(points.size());
  tape.x =
      attractorTrajectory(problem.reach.attractor, Eigen::VectorXd(startTaskVariables(problem)),
                          points, problem.reach.move_time / k, problem.reach.steps);
  TrajectoryCost c;
  forwardPass(problem, ik, tape, c, derivatives);
  return c;
}

/// The backward pass on a rollout taken with derivatives: c.gradient = dC/dP (T2, T3).
void addGradient(const TrajectoryProblem& problem, const ResolvedRateIK& ik, int k,
                 const Tape& tape, TrajectoryCost& c) {
  const std::vector<Eigen::VectorXd> dx = problem.step_derivative == StepDerivative::kAnalytic
                                              ? analyticBackwardPass(problem, ik, tape, c)
                                              : backwardPass(problem, ik, tape.x, c, tape.dq);
  const std::vector<Eigen::VectorXd> w = attractorWeights(problem, k);
  c.gradient = Eigen::VectorXd::Zero(6 * k);
  for (std::size_t t = 0; t < dx.size(); ++t)
    for (int j = 0; j < k; ++j) c.gradient.segment<6>(6 * j) += w[t][j + 1] * dx[t];
}

void checkPoints(const std::vector<Eigen::VectorXd>& points) {
  if (points.empty()) throw Error("trajectory: give at least one attractor point");
  for (const Eigen::VectorXd& point : points)
    if (point.size() != 6 || !point.allFinite())
      throw Error("trajectory: every attractor point needs 6 finite task variables");
}

}  // namespace

TrajectoryCost evaluateTrajectory(const TrajectoryProblem& problem,
                                  const std::vector<Eigen::VectorXd>& points, bool gradient) {
  problem.validate();
  checkPoints(points);
  const ResolvedRateIK ik = trajectoryIk(problem);
  Tape tape;
  TrajectoryCost c = rollOut(problem, ik, points, gradient, tape);
  if (gradient) addGradient(problem, ik, static_cast<int>(points.size()), tape, c);
  return c;
}

TrajectoryOptimization optimizeTrajectory(const TrajectoryProblem& problem,
                                          std::vector<Eigen::VectorXd> points,
                                          const TrajectoryOptimizerOptions& options) {
  options.validate();
  problem.validate();
  checkPoints(points);
  const ResolvedRateIK ik = trajectoryIk(problem);
  const int k = static_cast<int>(points.size());
  TrajectoryOptimization r;
  Tape tape;
  TrajectoryCost current = rollOut(problem, ik, points, true, tape);
  addGradient(problem, ik, k, tape, current);
  detail::reportIteration(r, current, options);  // iteration 0: the start
  double step = options.initial_step;
  r.status = TrajectoryStatus::kIterationLimit;
  for (r.iterations = 0; r.iterations < options.max_iterations;) {
    const double gnorm = current.gradient.norm();
    if (!(gnorm > 0.0)) {
      r.status = TrajectoryStatus::kConverged;
      break;
    }
    bool accepted = false;
    std::vector<Eigen::VectorXd> trial = points;
    TrajectoryCost candidate;
    for (int tries = 0; tries < 30 && !accepted; ++tries, step *= 0.5) {
      for (std::size_t j = 0; j < points.size(); ++j)
        trial[j] = points[j] - step * current.gradient.segment<6>(6 * j) / gnorm;
      // With derivatives: an accepted trial needs only its backward pass.
      candidate = rollOut(problem, ik, trial, true, tape);
      accepted = candidate.total < current.total - 1e-4 * step * gnorm;
    }
    if (!accepted) {
      r.status = TrajectoryStatus::kConverged;
      break;
    }
    step *= 4.0;  // undo the last halving and grow: the step adapts to the landscape
    const double previous = current.total;
    points = trial;
    current = std::move(candidate);
    addGradient(problem, ik, k, tape, current);
    if (detail::acceptIteration(r, current, previous, options)) break;
  }
  detail::finishDescent(r, std::move(points), std::move(current));
  return r;
}

}  // namespace taskmap
