// A map build from files to a file (taskmap build, taskmap-mpi build, taskmap.build): plan,
// lock, load, build, label, write.
#include "taskmap/builder/map_file_build.hpp"

#include <atomic>
#include <chrono>
#include <filesystem>
#include <utility>

#include <nlohmann/json.hpp>

#include "taskmap/builder/size_check.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/core/run_lock.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/meshes/object_size.hpp"
#include "taskmap/validate/validate_map.hpp"

namespace taskmap {

FileBuildPlan planFileBuild(const FileBuildOptions& o) {
  FileBuildPlan plan;
  plan.options = o.build;
  if (!(o.mesh.scale > 0.0)) throw Error("--scale must be positive");
  if (o.output.empty()) throw Error("-o MAP.h5 is required");
  const std::filesystem::path out_dir = std::filesystem::absolute(o.output).parent_path();
  if (!std::filesystem::is_directory(out_dir))
    throw Error("output directory '" + out_dir.string() + "' does not exist; create it first");
  plan.object = resolveObjectFile(o.object);
  plan.hand_urdf = resolveHandUrdf(o.hand);
  checkOutputPath(o.output, {plan.object, plan.hand_urdf, handSidecarPath(plan.hand_urdf)},
                  OutputKind::kTaskMap, o.force);
  checkOutputPath(o.output + ".ckpt", {plan.object, plan.hand_urdf}, OutputKind::kTaskMap, true,
                  "the checkpoint");
  nlohmann::json extra = {
      {"object", plan.object}, {"scale", o.mesh.scale}, {"hand", plan.hand_urdf}};
  if (o.mesh.wrap)
    extra["repair"] = {
        {"wrap", true}, {"alpha", o.mesh.wrap_alpha}, {"offset", o.mesh.wrap_offset}};
  if (!o.mesh.repair) extra["repair"] = false;
  plan.options.extra_params_json = extra.dump();
  plan.options.validate();
  return plan;
}

void checkGraspOptions(const BuildOptions& options, const HandModel& hand,
                       const std::string& hand_path) {
  const GraspMode mode = options.simulation.grasp_mode.value_or(hand.graspMode());
  if (options.simulation.standoff >= 0.0 && mode != GraspMode::kFingertip)
    throw Error("--standoff applies to fingertip grasps; add --grasp fingertip (hand '" +
                hand_path + "' grasps with the palm)");
}

std::optional<HoldLabels> labelHolds(HoldValidation validation, const BuildOptions& build,
                                     const HandModel& hand, const std::atomic<bool>* stop,
                                     TaskMapData* map) {
  if (validation == HoldValidation::kOff) return std::nullopt;
  const ClusteringOptions& clustering = build.clustering;
  ValidateOptions options;
  options.threads = build.threads;
  options.hold.integrator = build.hold_test_options.hold.integrator;
  ValidateControl control;
  control.stop = stop;
  const ValidationSummary s = validateMap(map, hand, options, control);
  if (s.status == ValidationSummary::Status::kInterrupted) return std::nullopt;
  HoldLabels labels;
  labels.tested = s.tested;
  labels.holding = s.holding;
  labels.cpu_seconds = s.cpu_seconds;
  labels.before = map->grasps.size();
  labels.kept = validation == HoldValidation::kKeepHolding ? keepHoldingGrasps(map, clustering)
                                                           : labels.before;
  if (labels.kept == 0)
    throw Error("--keep-holding: none of the " + std::to_string(labels.before) +
                " grasps holds in the physics test; nothing written");
  return labels;
}

struct MapFileBuild::Impl {
  // One build at a time per output: a second one refuses with the holder's PID.
  Impl(const std::string& output, const std::string& urdf)
      : lock(output + ".lock", "output '" + output + "'"), hand(HandModel::load(urdf)) {}
  RunLock lock;
  HandModel hand;
  std::optional<ObjectModel> object;
};

MapFileBuild::MapFileBuild(FileBuildOptions options)
    : request_(std::move(options)),
      plan_(planFileBuild(request_)),
      impl_(std::make_unique<Impl>(request_.output, plan_.hand_urdf)) {
  checkGraspOptions(plan_.options, impl_->hand, plan_.hand_urdf);
}

MapFileBuild::~MapFileBuild() = default;

const HandModel& MapFileBuild::hand() const {
  return impl_->hand;
}

const ObjectModel& MapFileBuild::loadObject() {
  if (impl_->object) return *impl_->object;
  const ScopedLoadBoundsCheck size_check(
      plan_.options.check_size
          ? sizeCheckOnLoad(impl_->hand, std::filesystem::path(plan_.object).stem().string(),
                            request_.mesh.scale)
          : nullptr);
  impl_->object.emplace(ObjectModel::load(plan_.object, request_.mesh));
  return *impl_->object;
}

FileBuildResult MapFileBuild::run(const BuildControl& control) {
  const ObjectModel& object = loadObject();
  FileBuildResult r;
  r.threads = buildThreadCount(plan_.options.threads);
  r.build = buildMap(object, impl_->hand, plan_.options, control);
  if (r.build.status == BuildStatus::kInterrupted || r.build.status == BuildStatus::kNoGrasps)
    return r;
  TaskMapData& map = r.build.map;
  if (request_.timestamp) map.created_utc = mapCreationTime(true);
  r.validation = labelHolds(request_.validation, plan_.options, impl_->hand, control.stop, &map);
  if (control.stopRequested()) {  // during the physics validation: nothing is written
    r.build.status = BuildStatus::kInterrupted;
    r.build.message = "interrupted during the physics validation; nothing written";
    r.validation.reset();
    return r;
  }
  const auto t_write = std::chrono::steady_clock::now();
  writeMap(request_.output, map);
  r.write_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_write).count();
  r.written = true;
  return r;
}

}  // namespace taskmap
