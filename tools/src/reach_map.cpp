// `taskmap reach --map`: plan with the map (reaching/map_reach.hpp), re-simulate the final grasp
// (builder/resimulate.hpp), print the measures of the issue (JSON or text), draw and write what
// was asked.
#include "reach_map.hpp"

#include <cstdio>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "command.hpp"
#include "taskmap/builder/resimulate.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/inspect/glb_export.hpp"
#include "taskmap/picture/reach_picture.hpp"
#include "taskmap/reaching/map_reach.hpp"
#include "taskmap/reaching/plan_report.hpp"
#include "taskmap/reaching/trajectory_record.hpp"

namespace taskmap::cli {

namespace {

/// -o trajectory.h5 and --glb out.glb of the chosen plan.
void writeOutputs(const MapReachArgs& args, const TrajectoryProblem& p, const TaskMap& map,
                  const MapReach& r, bool json) {
  if (args.output.empty() && args.glb.empty()) return;
  if (r.plan.best < 0) throw Error("no trajectory to write: " + r.plan.message);
  const TrajectoryRecord record =
      trajectoryRecord(*p.robot, p.body, p.reference, map, r.plan.plans[r.plan.best], r.movement,
                       {args.robot, args.hand, resolveMapFile(args.map), p.reach.attractor.dt,
                        r.plan.map_weights.quality_peak.value_or(1.0)});
  if (!args.output.empty()) writeTrajectory(args.output, record);
  if (!args.glb.empty()) writeGlb(record, args.glb);
  if (json) return;
  if (!args.output.empty()) std::printf("trajectory        %s\n", args.output.c_str());
  if (!args.glb.empty()) std::printf("glb               %s\n", args.glb.c_str());
}

GraspPlanOptions planOptions(const MapReachArgs& args) {
  if (args.iterations < 1) throw Error("--iterations must be >= 1");
  if (args.hold_test && !args.resimulate)
    throw Error("--hold-test tests the re-simulated grasp: drop --no-resimulate");
  const Descent descent = [&args] {
    try {
      return descentFromString(args.descent);
    } catch (const Error& e) {
      throw Error(std::string("--") + e.what());
    }
  }();
  GraspPlanOptions o;
  o.all_clusters = args.all_clusters;
  o.ranking.member_tries = args.member_tries;
  o.descent = descent;
  o.optimizer.max_iterations = args.iterations;
  o.map_weights.proximity = args.proximity_weight;
  o.map_weights.quality = args.quality_weight;
  return o;
}

}  // namespace

void runMapReach(const MapReachArgs& args, const TrajectoryProblem& p, bool json,
                 const std::string& png) {
  const GraspPlanOptions o = planOptions(args);
  TaskMapOptions map_options;
  map_options.sample_weight = sampleWeightFromString(args.sample_weight);
  const TaskMap map = TaskMap::load(resolveMapFile(args.map), map_options);
  const MapReach r = planMapReach(p, map, o);
  const GraspPlan& plan = r.plan;
  std::optional<Resimulation> resim;
  if (args.resimulate && plan.best >= 0)
    resim = resimulateGrasp(
        map.data(), finalPalmInObject(*p.robot, plan.plans[plan.best], p.body, p.reference));
  if (resim && args.hold_test) holdTestResimulated(map.data(), &*resim);
  if (json) {
    nlohmann::json j = nlohmann::json::parse(graspPlanReport(plan, r.plan_ms, r.movement));
    j["sample_weight"] = toString(map.options().sample_weight);
    if (resim) j["resimulated"] = nlohmann::json::parse(resimulationJson(*resim));
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << graspPlanText(plan, r.plan_ms);
    if (resim) std::cout << resimulationText(*resim);
  }
  if (!png.empty() && plan.best >= 0) {
    const ClusterPlan& b = plan.plans[plan.best];
    Kinematics kin(*p.robot);
    kin.update(p.q0);
    writeGraspPlanPictures(
        *p.robot, b, r.movement, p.body,
        kin.pose(p.reference) * map.pose(static_cast<std::size_t>(b.grasp_index)).toIsometry(),
        p.reach.attractor.dt, png);
  }
  writeOutputs(args, p, map, r, json);
  if (plan.status != GraspPlanStatus::kPlanned) {
    std::cerr << "taskmap reach: " << plan.message << "\n";
    exitCode() = 1;
  }
}

}  // namespace taskmap::cli
