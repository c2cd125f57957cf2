// Python bindings of the reaching stage (docs/REACHING.md): taskmap.Robot (model, forward
// kinematics, Jacobians) and taskmap.reach (attractor + IK rollout). Configurations and
// Jacobians are numpy arrays; poses 4x4 matrices or (x y z qw qx qy qz) vectors.
#include "reaching_bindings.hpp"

#include "offline_docs.hpp"

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "taskmap/builder/resimulate.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/pose.hpp"
#include "taskmap/reaching/attractor.hpp"
#include "taskmap/reaching/grasp_planner.hpp"
#include "taskmap/reaching/map_reach.hpp"
#include "taskmap/reaching/movement_terms.hpp"
#include "taskmap/reaching/plan_report.hpp"
#include "taskmap/reaching/reach_scene.hpp"
#include "taskmap/reaching/robot_costs.hpp"

namespace py = pybind11;

namespace taskmap {
namespace {

/// A robot with its environment; `object` names the grasped body ("" if none).
struct PyRobot {
  RobotModel model;
  std::string object;
};

int bodyOf(const PyRobot& r, const std::string& name) {
  return name.empty() ? -1 : r.model.requireBody(name);
}

Kinematics kinematicsAt(const PyRobot& r, const Eigen::VectorXd& q) {
  Kinematics kin(r.model);
  kin.update(q);
  return kin;
}

/// A grasp-planning problem of a robot with a scene object: its collision pairs (the hand may
/// touch the object) and the trajectory problem of the palm relative to the object from q0
/// (default: the middle of the joint ranges). Throws Error prefixed with `what`.
struct GraspProblem {
  std::unique_ptr<CollisionModel> collisions;  ///< pairs, owned (the problem points to them)
  TrajectoryProblem problem;                   ///< palm relative to the scene object
};

GraspProblem graspProblem(const PyRobot& r, const std::optional<Eigen::VectorXd>& q0,
                          const std::string& what) {
  if (r.object.empty()) throw Error(what + ": a map needs a robot with a scene object (add_scene)");
  if (r.model.palmBody() < 0) throw Error(what + ": a map needs a robot with a hand");
  CollisionOptions co;
  co.hand_may_touch = {r.object};
  GraspProblem g;
  g.collisions = std::make_unique<CollisionModel>(r.model, co);
  g.problem.robot = &r.model;
  g.problem.collisions = g.collisions.get();
  g.problem.body = r.model.palmBody();
  g.problem.reference = r.model.requireBody(r.object);
  g.problem.q0 = q0 ? *q0 : r.model.midConfiguration();
  return g;
}

/// Configurations (rad) as the rows of one matrix (steps+1 x dofs).
Eigen::MatrixXd jointMatrix(const std::vector<Eigen::VectorXd>& q) {
  Eigen::MatrixXd m(q.size(), q.front().size());
  for (std::size_t t = 0; t < q.size(); ++t) m.row(static_cast<Eigen::Index>(t)) = q[t].transpose();
  return m;
}

py::dict planDict(const GraspPlan& plan) {
  py::dict d;
  d["status"] = toString(plan.status);
  d["message"] = plan.message;
  if (plan.best < 0) return d;
  const ClusterPlan& b = plan.plans[plan.best];
  d["cluster"] = b.grasp_cluster;
  d["grasp_index"] = b.grasp_index;
  d["iterations"] = b.optimization.iterations;
  d["iterations_to_manifold"] = b.iterations_to_manifold;
  d["iterations_to_quality"] = b.iterations_to_quality;
  d["min_clearance_m"] = b.min_clearance;
  d["joint_limit_margin_rad"] = b.joint_limit_margin;
  d["collision_free"] = b.collision_free;
  d["ms_per_iteration"] = b.milliseconds / std::max(1, b.optimization.iterations);
  std::vector<double> total;
  for (const TrajectoryCost& c : b.optimization.history) total.push_back(c.total);
  d["cost_history"] = total;
  d["proximity_history"] = b.proximity;
  d["quality_history"] = b.quality;
  d["q"] = jointMatrix(b.optimization.cost.q);
  return d;
}

/// The report of `taskmap reach --map --json` (graspPlanReport) plus q (steps+1 x dofs, rad) of
/// the best plan.
py::dict mapReachDict(const GraspPlan& plan, double plan_ms, const MovementTerms& movement) {
  py::dict d = py::module_::import("json").attr("loads")(graspPlanReport(plan, plan_ms, movement));
  if (plan.best < 0) return d;
  d["q"] = jointMatrix(plan.plans[static_cast<std::size_t>(plan.best)].optimization.cost.q);
  return d;
}

py::dict reachDict(const ReachResult& res) {
  py::dict d;
  d["status"] = res.status == ReachStatus::kReached    ? "reached"
                : res.status == ReachStatus::kCollided ? "collided"
                                                       : "not_reached";
  d["message"] = res.message;
  d["q"] = jointMatrix(res.q);
  d["position_error"] = res.position_error;
  d["orientation_error"] = res.orientation_error;
  d["min_clearance"] = std::isfinite(res.min_clearance) ? py::object(py::float_(res.min_clearance))
                                                        : py::object(py::none());
  d["min_clearance_pair"] = res.min_clearance_pair;
  d["joint_limit_margin"] = res.joint_limit_margin;
  return d;
}

/// taskmap.Robot: the arm, its hand and scene, kinematics.
void bindRobot(py::module_& m) {
  py::class_<PyRobot>(m, "Robot", pydoc::kRobot)
      .def_static(
          "load",
          [](const std::string& urdf) {
            return PyRobot{RobotModel::load(urdf), ""};
          },
          py::arg("urdf"), pydoc::kRobotLoad)
      .def_static(
          "panda_with_humanoid_hand",
          [](const std::string& robots_dir, const std::string& hands_dir) {
            return PyRobot{RobotModel::pandaWithHumanoidHand(robots_dir, hands_dir), ""};
          },
          py::arg("robots_dir"), py::arg("hands_dir"), pydoc::kRobotPandaHumanoid)
      .def(
          "add_scene",
          [](PyRobot& r, const std::string& path) {
            const ReachScene scene = path.empty() ? defaultReachScene() : loadReachScene(path);
            addSceneTo(scene, r.model);
            r.object = scene.object;
          },
          py::arg("path") = "", pydoc::kRobotAddScene)
      .def_property_readonly(
          "dofs", [](const PyRobot& r) { return r.model.dofs(); }, "Number of joints.")
      .def_property_readonly(
          "dof_names", [](const PyRobot& r) { return r.model.dofNames(); },
          "The joints' names, in the order of q.")
      .def_property_readonly(
          "lower", [](const PyRobot& r) { return r.model.lower(); },
          "Lower joint limits (radians; metres for prismatic joints).")
      .def_property_readonly(
          "upper", [](const PyRobot& r) { return r.model.upper(); },
          "Upper joint limits (radians; metres for prismatic joints).")
      .def_property_readonly(
          "object", [](const PyRobot& r) { return r.object; },
          "The scene's object body ('' before add_scene).")
      .def_property_readonly(
          "body_names",
          [](const PyRobot& r) {
            std::vector<std::string> names;
            for (const RobotBody& b : r.model.bodies()) names.push_back(b.name);
            return names;
          },
          "Every body's name, parents first (the hand's links and 'palm' included).")
      .def(
          "forward_kinematics",
          [](const PyRobot& r, const Eigen::VectorXd& q) {
            const Kinematics kin = kinematicsAt(r, q);
            std::vector<Eigen::Matrix4d> poses;
            for (size_t i = 0; i < r.model.bodies().size(); ++i)
              poses.push_back(kin.pose(static_cast<int>(i)).matrix());
            return poses;
          },
          py::arg("q"), pydoc::kRobotFk)
      .def(
          "jacobian",
          [](const PyRobot& r, const Eigen::VectorXd& q, const std::string& body,
             const std::string& reference) {
            const Kinematics kin = kinematicsAt(r, q);
            const int b = r.model.requireBody(body), ref = bodyOf(r, reference);
            Eigen::MatrixXd j(6, r.model.dofs());
            j.topRows(3) = kin.relativePositionJacobian(b, ref);
            j.bottomRows(3) = kin.relativeAngularJacobian(b, ref);
            return j;
          },
          py::arg("q"), py::arg("body"), py::arg("reference") = "", pydoc::kRobotJacobian);
}

/// taskmap.reach and taskmap.plan_grasp.
void bindPlanning(py::module_& m) {
  m.def(
      "reach",
      [](const PyRobot& r, const Eigen::Matrix<double, 7, 1>& target, const std::string& body,
         const std::string& reference, const std::optional<Eigen::VectorXd>& q0, int steps,
         double dt, double relaxation_time, double move_time, bool avoid_collisions) {
        ReachOptions o;
        o.steps = steps;
        o.attractor.dt = dt;
        o.attractor.relaxation_time = relaxation_time;
        o.move_time = move_time;
        if (!avoid_collisions) o.ik.collision_gain = 0.0;
        CollisionOptions co;
        if (!r.object.empty()) co.hand_may_touch = {r.object};
        const CollisionModel collisions(r.model, co);
        const int b = body.empty() ? r.model.palmBody() : r.model.requireBody(body);
        if (b < 0) throw Error("reach: the robot has no hand; name the body to move (body=...)");
        const std::string ref = reference == "object" ? r.object : reference;
        if (reference == "object" && r.object.empty())
          throw Error("reach: reference 'object' needs a scene with an object (add_scene)");
        return reachDict(reach(r.model, &collisions, b, bodyOf(r, ref),
                               Pose::fromVector7(target).toIsometry(),
                               q0 ? *q0 : r.model.midConfiguration(), o));
      },
      py::arg("robot"), py::arg("target"), py::arg("body") = "", py::arg("reference") = "object",
      py::arg("q0") = py::none(), py::arg("steps") = 300, py::arg("dt") = 0.01,
      py::arg("relaxation_time") = 0.2, py::arg("move_time") = 1.0,
      py::arg("avoid_collisions") = true, pydoc::kReachTarget);

  m.def(
      "reach",
      [](const PyRobot& r, const TaskMap& map, const std::optional<Eigen::VectorXd>& q0,
         bool all_clusters, int iterations, double proximity_weight, double quality_weight,
         int steps, double dt, const std::string& descent, std::optional<bool> resimulate_arg,
         bool hold_test, int member_tries) {
        if (hold_test && resimulate_arg == false)
          throw Error("reach: hold_test tests the re-simulated grasp: drop resimulate=False");
        // As the CLI: a built map (its hand and object recorded) is re-simulated by default.
        const TaskMapData& data = map.data();
        const bool resimulate = resimulate_arg.value_or(!data.hand.urdf_sha256.empty() &&
                                                        data.object.vertices.rows() > 0);
        GraspProblem g = graspProblem(r, q0, "reach");
        TrajectoryProblem& p = g.problem;
        p.reach.steps = steps;
        p.reach.attractor.dt = dt;
        GraspPlanOptions o;
        try {
          o.descent = descentFromString(descent);
        } catch (const Error& e) {
          throw Error(std::string("reach: ") + e.what());
        }
        o.all_clusters = all_clusters;
        o.ranking.member_tries = member_tries;
        o.optimizer.max_iterations = iterations;
        o.map_weights.proximity = proximity_weight;
        o.map_weights.quality = quality_weight;
        const MapReach planned = planMapReach(p, map, o);
        py::dict d = mapReachDict(planned.plan, planned.plan_ms, planned.movement);
        if (resimulate && planned.plan.best >= 0) {
          Resimulation rs = resimulateGrasp(
              map.data(), finalPalmInObject(r.model, planned.plan.plans[planned.plan.best], p.body,
                                            p.reference));
          if (hold_test) holdTestResimulated(map.data(), &rs);
          d["resimulated"] = py::module_::import("json").attr("loads")(resimulationJson(rs));
        }
        return d;
      },
      py::arg("robot"), py::arg("map"), py::arg("q0") = py::none(), py::arg("all_clusters") = false,
      py::arg("iterations") = 40, py::arg("proximity_weight") = 1.0e4,
      py::arg("quality_weight") = 3.0e4, py::arg("steps") = 300, py::arg("dt") = 0.01,
      py::arg("descent") = "bfgs", py::arg("resimulate") = py::none(), py::arg("hold_test") = false,
      py::arg("member_tries") = 16, pydoc::kReachMap);

  m.def(
      "plan_grasp",
      [](const PyRobot& r, const TaskMap& map, const std::optional<Eigen::VectorXd>& q0,
         bool all_clusters, int iterations, double proximity_weight, double quality_weight,
         int member_tries) {
        const GraspProblem g = graspProblem(r, q0, "plan_grasp");
        const TrajectoryProblem& p = g.problem;
        GraspPlanOptions o;
        o.all_clusters = all_clusters;
        o.ranking.member_tries = member_tries;
        o.optimizer.max_iterations = iterations;
        o.map_weights.proximity = proximity_weight;
        o.map_weights.quality = quality_weight;
        return planDict(planGrasp(p, map, o));
      },
      py::arg("robot"), py::arg("map"), py::arg("q0") = py::none(), py::arg("all_clusters") = false,
      py::arg("iterations") = 40, py::arg("proximity_weight") = 1.0e4,
      py::arg("quality_weight") = 3.0e4, py::arg("member_tries") = 16, pydoc::kPlanGrasp);
}

}  // namespace

/// End-state comfort costs (robot_costs.hpp).
void bindCosts(py::module_& m) {
  m.def(
      "joint_limit_cost",
      [](const Eigen::VectorXd& q, const Eigen::VectorXd& lo, const Eigen::VectorXd& hi) {
        return jointLimitCost(q, lo, hi);
      },
      py::arg("q"), py::arg("lower"), py::arg("upper"), pydoc::kJointLimitCost);
  m.def("collision_cost", &collisionCost, py::arg("distances"), py::arg("zone"),
        py::arg("scale") = 1.0, pydoc::kCollisionCost);
}

void bindReaching(py::module_& m) {
  bindRobot(m);
  bindPlanning(m);
  bindCosts(m);
}

}  // namespace taskmap
