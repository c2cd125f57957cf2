// taskmap reach --robot panda --target "x y z qw qx qy qz" [--scene FILE] [--json] [--png FILE]:
// move the hand to a fixed target with attractor dynamics and resolved-rate IK, avoiding the
// scene (reaching/, docs/REACHING.md).
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "command.hpp"
#include "mesh_options.hpp"
#include "reach_map.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/core/pose.hpp"
#include "taskmap/core/text.hpp"
#include "taskmap/picture/reach_picture.hpp"
#include "taskmap/reaching/attractor.hpp"
#include "taskmap/reaching/map_reach.hpp"
#include "taskmap/reaching/plan_report.hpp"
#include "taskmap/reaching/reach_scene.hpp"

namespace taskmap::cli {
namespace {

struct ReachArgs {
  std::string robot = "panda", hand = "humanoid", flange, mount, target, frame, scene, start, png;
  std::vector<std::string> via;
  ReachOptions options;
  MapReachArgs map;
  bool json = false;
  bool force = false;
};

/// -o, --glb and --png against the inputs (output_guard.hpp), before any work.
void checkReachOutputs(const ReachArgs& args) {
  std::vector<std::string> inputs = {args.scene, args.robot, args.hand};
  if (!args.map.map.empty()) {
    inputs.push_back(args.map.map);
    try {
      inputs.push_back(resolveMapFile(args.map.map));  // a bundled map name
    } catch (const Error&) {
      // not a map: reported with the other options' checks
    }
  }
  checkOutputPath(args.map.output, inputs, OutputKind::kTaskMap, args.force, "-o");
  checkOutputPath(args.map.glb, inputs, OutputKind::kGlb, args.force, "--glb");
  checkOutputPath(args.png, inputs, OutputKind::kPng, args.force, "--png");
  const std::string outputs[] = {args.map.output, args.map.glb, args.png};
  for (std::size_t a = 0; a < 3; ++a)
    for (std::size_t b = a + 1; b < 3; ++b)
      if (!outputs[a].empty() && outputs[a] == outputs[b])
        throw Error("'" + outputs[a] +
                    "' is named by two of -o, --glb and --png; give each its own file");
}

/// The robot with its hand (if any) and the scene (reaching/map_reach.hpp).
ReachRobot buildRobot(const ReachArgs& args, const ReachScene& scene) {
  ReachRobotOptions o;
  o.robot = args.robot;
  o.hand = args.hand;
  o.flange = args.flange;
  if (!args.mount.empty()) o.mount = parsePoseText(args.mount, "--mount");
  return loadReachRobot(o, scene);
}

Eigen::VectorXd startConfiguration(const ReachArgs& args, const RobotModel& robot) {
  if (!args.start.empty()) return parseNumbers(args.start, robot.dofs(), "--start");
  ReachRobotOptions o;
  o.robot = args.robot;
  return reachStartConfiguration(o, robot);
}

/// The map mode: the object placed at --object-pose, the grasp chosen on the map.
void runReachWithMap(const ReachArgs& args) {
  if (!args.target.empty()) throw Error("--target and --map exclude each other");
  if (args.map.object_pose.empty()) throw Error("--map needs --object-pose \"x y z yaw\"");
  ReachScene scene = args.scene.empty() ? defaultReachScene() : loadReachScene(args.scene);
  if (scene.object.empty()) throw Error("--map needs a scene with an \"object\" body");
  for (SceneBody& b : scene.bodies)
    if (b.name == scene.object) b.pose = parseXyzYaw(args.map.object_pose, "--object-pose");
  const ReachRobot robot = buildRobot(args, scene);
  if (robot.body != robot.model.palmBody())
    throw Error("--map needs a hand on the robot (its palm frame)");
  CollisionOptions co;
  co.hand_may_touch = {scene.object};
  const CollisionModel collisions(robot.model, co);
  MapReachArgs map_args = args.map;
  map_args.robot = args.robot;
  map_args.hand = args.hand;
  TrajectoryProblem p;
  p.robot = &robot.model;
  p.collisions = &collisions;
  p.body = robot.body;
  p.reference = robot.model.requireBody(scene.object);
  p.q0 = startConfiguration(args, robot.model);
  p.reach = args.options;
  runMapReach(map_args, p, args.json, args.png);
}

void runReach(const ReachArgs& args) {
  args.options.validate();
  checkReachOutputs(args);
  if (!args.map.map.empty()) return runReachWithMap(args);
  if (!args.map.output.empty() || !args.map.glb.empty())
    throw Error("-o/--output and --glb write the trajectory of a plan with --map MAP");
  if (args.target.empty()) throw Error("--target \"x y z qw qx qy qz\" (or --map) is required");
  const Eigen::Isometry3d target = parsePoseText(args.target, "--target");
  ReachOptions options = args.options;
  for (const std::string& v : args.via) options.via_points.push_back(parsePoseText(v, "--via"));
  const ReachScene scene = args.scene.empty() ? defaultReachScene() : loadReachScene(args.scene);
  const ReachRobot loaded = buildRobot(args, scene);
  const RobotModel& robot = loaded.model;
  const int body = loaded.body;
  const std::string frame = !args.frame.empty()    ? args.frame
                            : scene.object.empty() ? "world"
                                                   : "object";
  if (frame != "world" && frame != "object") throw Error("--frame must be 'world' or 'object'");
  if (frame == "object" && scene.object.empty())
    throw Error("--frame object needs a scene with an \"object\" body");
  const int reference = frame == "object" ? robot.requireBody(scene.object) : -1;
  CollisionOptions co;
  if (!scene.object.empty()) co.hand_may_touch = {scene.object};
  const CollisionModel collisions(robot, co);
  const Eigen::VectorXd q0 = startConfiguration(args, robot);
  const auto t0 = std::chrono::steady_clock::now();
  const ReachResult r = reach(robot, &collisions, body, reference, target, q0, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ReachReportContext report{args.robot,
                            args.hand,
                            frame,
                            parseNumbers(args.target, 7, "--target"),
                            options.attractor.dt,
                            collisions.pairs().size(),
                            seconds};
  std::cout << (args.json ? reachReport(r, report) + "\n" : reachText(r, report));
  if (!args.png.empty()) {
    Kinematics kin(robot);
    const Eigen::Isometry3d ref =
        reference >= 0 ? kin.pose(reference) : Eigen::Isometry3d::Identity();
    const int n = static_cast<int>(r.q.size()) - 1;
    writeReachPicture(robot, r, body, {0, n / 4, n / 2, n}, ref * target, args.png);
    if (!args.json) std::printf("picture           %s\n", args.png.c_str());
  }
  if (r.status != ReachStatus::kReached) {
    std::cerr << "taskmap reach: " << r.message << "\n";
    exitCode() = 1;
  }
}

const CommandRegistrar kRegistrar(
    "reach", "Plan an arm's reach to a palm pose, or to a grasp of a task map (--map)",
    [](CLI::App& app) {
      auto args = std::make_shared<ReachArgs>();
      CLI::App* cmd = app.add_subcommand("reach",
                                         "Move the hand to a fixed palm pose with attractor "
                                         "dynamics and resolved-rate IK, avoiding "
                                         "the table and the object (joint-limit and collision "
                                         "null-space terms). Exit status 1 when "
                                         "the target is not reached or a collision occurs.");
      cmd->add_option("--robot", args->robot, "'panda' (the bundled Franka arm) or a robot URDF")
          ->capture_default_str();
      cmd->add_option("--hand", args->hand,
                      "hand on the flange: a name under meshes/hands, a hand URDF, or 'none'")
          ->capture_default_str();
      cmd->add_option("--flange", args->flange, "link the hand is mounted on (default fer_link8)");
      addPackagePathOption(cmd);
      cmd->add_option("--mount", args->mount,
                      "palm frame in the flange frame \"x y z qw qx qy qz\" (default: the hand "
                      "sidecar's \"mount\"; a hand without one needs this option)");
      cmd->add_option("--target", args->target, "target palm pose \"x y z qw qx qy qz\" (metres)");
      cmd->add_option("--map", args->map.map,
                      "task map of the mounted hand (a file or a bundled map name, e.g. "
                      "basket_humanoid): optimise the reach over attractor points with "
                      "the map as the target (needs --object-pose)");
      cmd->add_option("--object-pose", args->map.object_pose,
                      "with --map: object pose in the world \"x y z yaw\" (metres, radians)");
      cmd->add_flag("--all-clusters", args->map.all_clusters,
                    "with --map: optimise from every reachable cluster and keep the cheapest");
      cmd->add_option("--member-tries", args->map.member_tries,
                      "with --map: when no cluster's representative grasp is in reach, or when "
                      "every plan from them is unsafe, try at most this many other members of "
                      "each cluster, then as many outliers (0: the representatives only)")
          ->capture_default_str()
          ->check(CLI::NonNegativeNumber);
      cmd->add_option("--iterations", args->map.iterations, "with --map: optimiser iterations")
          ->capture_default_str();
      cmd->add_option("--proximity-weight", args->map.proximity_weight, "with --map: w_map,p")
          ->capture_default_str();
      cmd->add_option("--quality-weight", args->map.quality_weight,
                      "with --map: w_map,q on the map's quality relative to its best grasp, "
                      "g_q / q* (-1 there; 0 switches the quality criterion off)")
          ->capture_default_str();
      cmd->add_option(
          "-o,--output", args->map.output,
          "with --map: write the planned trajectory (joints, palm and body poses per "
          "step, cost history; mapstore/TRAJECTORY.md); `taskmap export-glb` renders it");
      cmd->add_option("--glb", args->map.glb,
                      "with --map: also write the trajectory as glTF binary for Blender");
      cmd->add_option(
             "--descent", args->map.descent,
             "with --map: 'bfgs' (quasi-Newton) or 'gradient' (normalised steepest descent)")
          ->capture_default_str();
      cmd->add_flag("--resimulate,!--no-resimulate", args->map.resimulate,
                    "with --map: re-simulate the final grasp with grasp_sim on the map's hand and "
                    "object (JSON \"resimulated\"; default on)");
      cmd->add_option("--sample-weight", args->map.sample_weight,
                      "with --map: what weighs each map sample in the quality term: 'epsilon', "
                      "'hold_margin' (epsilon x physics hold margin; needs a validated map) or "
                      "'auto' (hold_margin when every grasp has a hold label)")
          ->capture_default_str();
      cmd->add_flag("--hold-test", args->map.hold_test,
                    "with --map: also test the re-simulated grasp in physics (the validator's "
                    "protocol, docs/VALIDATION.md; JSON \"resimulated\".\"hold\")");
      cmd->add_option("--via", args->via,
                      "intermediate palm pose \"x y z qw qx qy qz\" (same frame as --target) the "
                      "attractor point passes through; repeat for several");
      cmd->add_option("--frame", args->frame,
                      "frame of --target: 'object' (default when the scene has one) or 'world'");
      cmd->add_option("--scene", args->scene,
                      "scene JSON (docs/REACHING.md); default: a table and an upright cylinder");
      cmd->add_option("--start", args->start, "start configuration, one value per joint");
      cmd->add_option("--steps", args->options.steps, "control steps")->capture_default_str();
      cmd->add_option("--dt", args->options.attractor.dt, "sampling time, seconds")
          ->capture_default_str();
      cmd->add_option("--relaxation-time", args->options.attractor.relaxation_time,
                      "attractor relaxation time T_mc, seconds")
          ->capture_default_str();
      cmd->add_option("--move-time", args->options.move_time,
                      "seconds for the attractor point to reach the target")
          ->capture_default_str();
      cmd->add_flag("--json", args->json,
                    "print JSON: status, message, steps, dt_s, position_error_m, "
                    "orientation_error_rad, collision_pairs, min_clearance_m (null without pairs), "
                    "min_clearance_pair, min_clearance_step, joint_limit_margin, q_start, q_final, "
                    "palm_final [x y z qw qx qy qz], compute_time_s; with --map: iterations, "
                    "iterations_to_manifold, iterations_to_quality, cluster, grasp_index, "
                    "min_clearance_m, joint_limit_margin_rad, collision_free, ms_per_iteration, "
                    "cost_history, proximity_over_movement, quality_over_movement, plans (per "
                    "cluster), ranking, resimulated {outcome, force_closure, epsilon, contacts}");
      cmd->add_option("--png", args->png,
                      "also draw robot and scene (top, front, side) at 4 steps");
      cmd->add_flag("--force", args->force,
                    "replace existing -o/--glb/--png files that are not of their kind");
      cmd->callback([args] { runReach(*args); });
    });

}  // namespace
}  // namespace taskmap::cli
