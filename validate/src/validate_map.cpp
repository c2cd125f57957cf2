// Labels a map's grasps with the hold test on worker threads. Steps: check the hand against
// the map, build the tester, test grasps in index order across threads (each result depends on
// its grasp only), summarise, store.
#include "taskmap/validate/validate_map.hpp"

#include <chrono>
#include <ctime>
#include <filesystem>
#include <mutex>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

double cpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

void checkHand(const TaskMapData& map, const HandModel& hand) {
  if (hand.jointNames() != map.hand.joint_names)
    throw Error("validate: hand '" + hand.name() + "' (" + hand.urdfPath() +
                ") does not have the actuated joints of the map's hand '" + map.hand.name +
                "'; pass the hand the map was built with");
}

/// Runs the tests of grasps [0, n) on `threads` workers; results[i] is grasp i's.
bool runTests(const HoldTester& tester, const TaskMapData& map, std::size_t n, int threads,
              std::vector<HoldResult>* results, const ValidateControl& control) {
  results->assign(n, HoldResult{});
  std::atomic<std::size_t> next{0}, done{0}, holding{0};
  std::atomic<bool> failed{false};
  std::string error;
  std::mutex error_mutex;
  auto worker = [&] {
    for (;;) {
      if (control.stopRequested() || failed.load()) return;
      const std::size_t i = next.fetch_add(1);
      if (i >= n) return;
      try {
        const Eigen::VectorXd q = map.grasps.joints.row(static_cast<Eigen::Index>(i)).transpose();
        (*results)[i] = tester.test(map.grasps.poseAt(i), q);
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!failed.exchange(true)) error = "grasp " + std::to_string(i) + ": " + e.what();
        return;
      }
      holding += (*results)[i].holds ? 1 : 0;
      ++done;
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
  const auto report = [&] {
    if (control.progress) control.progress({done.load(), n, holding.load()});
  };
  try {
    while (done.load() < n && !failed.load() && !control.stopRequested()) {
      report();
      std::this_thread::sleep_for(std::chrono::duration<double>(control.interval_seconds));
    }
  } catch (...) {  // the callback threw: stop the workers, then pass it on
    failed.store(true);
    for (auto& th : pool) th.join();
    throw;
  }
  for (auto& th : pool) th.join();
  if (failed) throw Error("validate: " + error);
  report();
  return done.load() == n;
}

MapValidation labels(const std::vector<HoldResult>& results, std::size_t n,
                     const HoldTestOptions& options) {
  MapValidation v;
  v.hold.assign(n, MapValidation::kNotTested);
  v.status.assign(n, MapValidation::kNotTested);
  v.translation.assign(n, -1.0);
  v.rotation.assign(n, -1.0);
  v.direction.assign(n, -1);
  for (std::size_t i = 0; i < results.size(); ++i) {
    const HoldResult& r = results[i];
    v.hold[i] = r.holds ? 1 : 0;
    v.status[i] = static_cast<std::uint8_t>(r.status);
    v.translation[i] = r.max_translation;
    v.rotation[i] = r.max_rotation;
    v.direction[i] = r.failed_direction;
  }
  v.protocol = "dexgraspbench_fc";
  v.engine = physicsEngine();
  v.params_json = holdParamsJson(options);
  return v;
}

}  // namespace

void ValidateOptions::validate() const {
  hold.validate();
  if (threads < 0) throw Error("validate: threads (--threads) must be >= 0 (0: all cores)");
}

std::string summaryJson(const ValidationSummary& s) {
  nlohmann::ordered_json j;
  j["tested"] = s.tested;
  j["holding"] = s.holding;
  j["hold_rate"] = s.tested ? static_cast<double>(s.holding) / static_cast<double>(s.tested) : 0.0;
  j["force_closure_tested"] = s.fc_tested;
  j["force_closure_holding"] = s.fc_holding;
  j["statuses"] = s.statuses;
  nlohmann::ordered_json dirs;
  for (std::size_t d = 0; d < 6; ++d) dirs[pushDirectionNames()[d]] = s.failed_by_direction[d];
  j["slipped_by_direction"] = dirs;
  j["object_pieces"] = s.model.object_pieces;
  j["object_volume_error"] = s.model.object_volume_error;
  j["object_note"] = s.model.object_note;
  j["cpu_seconds"] = s.cpu_seconds;
  j["wall_seconds"] = s.wall_seconds;
  j["grasps_per_cpu_second"] =
      s.cpu_seconds > 0 ? static_cast<double>(s.tested) / s.cpu_seconds : 0.0;
  j["steps"] = s.steps;
  return j.dump();
}

std::string holdParamsJson(const HoldTestOptions& o) {
  nlohmann::ordered_json j;
  j["object_mass"] = o.object_mass;
  j["sliding_friction"] = o.sliding_friction;
  j["torsional_friction"] = o.torsional_friction;
  j["timestep"] = o.timestep;
  j["integrator"] = "implicit";
  j["cone"] = "elliptic";
  j["impratio"] = o.impratio;
  j["noslip_iterations"] = o.noslip_iterations;
  j["kp_revolute"] = o.kp_revolute;
  j["joint_damping"] = o.joint_damping;
  j["link_density"] = o.link_density;
  j["jaw_force"] = o.jaw_force;
  j["kp_prismatic"] = o.kp_prismatic;
  j["revolute_gripper_force"] = o.revolute_gripper_force;
  j["revolute_gripper_linkage"] = o.revolute_gripper_linkage;
  j["prismatic_damping"] = o.prismatic_damping;
  j["prismatic_armature"] = o.prismatic_armature;
  j["revolute_armature"] = o.revolute_armature;
  j["pregrasp_fraction"] = o.pregrasp_fraction;
  j["squeeze_fraction"] = o.squeeze_fraction;
  j["interpolation_stages"] = o.interpolation_stages;
  j["steps_per_stage"] = o.steps_per_stage;
  j["push_per_mass"] = o.push_per_mass;
  j["push_duration"] = o.push_duration;
  j["check_every"] = o.check_every;
  j["max_translation"] = o.max_translation;
  j["max_rotation"] = o.max_rotation;
  j["max_penetration"] = o.max_penetration;
  j["contact_patch"] = o.contact_patch;
  j["object_max_pieces"] = o.object_max_pieces;
  return j.dump();
}

namespace {

/// Copies row i of the grasps (and its contacts) from `in` to the end of `out`.
void appendRow(const MapGrasps& in, std::size_t i, MapGrasps* out, Eigen::Index row) {
  out->pose.row(row) = in.pose.row(static_cast<Eigen::Index>(i));
  out->joints.row(row) = in.joints.row(static_cast<Eigen::Index>(i));
  out->force_closure.push_back(in.force_closure[i]);
  out->epsilon.push_back(in.epsilon[i]);
  out->volume.push_back(in.volume[i]);
  const auto first = in.contact_offsets[i], last = in.contact_offsets[i + 1];
  const auto m = static_cast<Eigen::Index>(out->contact_offsets.back());
  out->contact_points.conservativeResize(m + (last - first), 3);
  out->contact_normals.conservativeResize(m + (last - first), 3);
  for (auto r = first; r < last; ++r) {
    out->contact_points.row(m + (r - first)) = in.contact_points.row(r);
    out->contact_normals.row(m + (r - first)) = in.contact_normals.row(r);
    out->contact_depths.push_back(in.contact_depths[static_cast<std::size_t>(r)]);
    out->contact_links.push_back(in.contact_links[static_cast<std::size_t>(r)]);
  }
  out->contact_offsets.push_back(m + (last - first));
}

}  // namespace

std::size_t keepHoldingGrasps(TaskMapData* map, const ClusteringOptions& clustering) {
  if (!map->validation)
    throw Error("keep holding grasps: the map has no hold labels; validate it first");
  const MapGrasps& in = map->grasps;
  const MapValidation& v = *map->validation;
  std::vector<std::size_t> keep;
  for (std::size_t i = 0; i < in.size(); ++i)
    if (v.hold[i] == 1) keep.push_back(i);
  MapGrasps out;
  out.contacts_available = in.contacts_available;
  out.rotation_scale = in.rotation_scale;
  out.pose.resize(static_cast<Eigen::Index>(keep.size()), in.pose.cols());
  out.joints.resize(static_cast<Eigen::Index>(keep.size()), in.joints.cols());
  out.contact_points.resize(0, 3);
  out.contact_normals.resize(0, 3);
  out.contact_offsets = {0};
  MapValidation labels = v;
  labels.hold.clear();
  labels.status.clear();
  labels.translation.clear();
  labels.rotation.clear();
  labels.direction.clear();
  for (std::size_t k = 0; k < keep.size(); ++k) {
    const std::size_t i = keep[k];
    appendRow(in, i, &out, static_cast<Eigen::Index>(k));
    labels.hold.push_back(v.hold[i]);
    labels.status.push_back(v.status[i]);
    labels.translation.push_back(v.translation[i]);
    labels.rotation.push_back(v.rotation[i]);
    labels.direction.push_back(v.direction[i]);
  }
  const bool clustered = map->clustering.has_value();
  map->grasps = std::move(out);
  map->validation = std::move(labels);
  map->clustering.reset();
  if (clustered && keep.size() >= 2) {
    std::vector<Pose> poses;
    for (std::size_t i = 0; i < keep.size(); ++i) poses.push_back(map->grasps.poseAt(i));
    ClusteringOptions co = clustering;
    co.rotation_scale = map->grasps.rotation_scale;
    map->clustering = clusterGrasps(poses, map->grasps.epsilon, co);
  }
  return keep.size();
}

ObjectModel mapObjectModel(const TaskMapData& map) {
  TriangleMesh mesh;
  const MapObject& o = map.object;
  for (Eigen::Index r = 0; r < o.vertices.rows(); ++r)
    mesh.vertices.emplace_back(o.vertices(r, 0), o.vertices(r, 1), o.vertices(r, 2));
  for (Eigen::Index r = 0; r < o.faces.rows(); ++r)
    mesh.faces.emplace_back(static_cast<int>(o.faces(r, 0)), static_cast<int>(o.faces(r, 1)),
                            static_cast<int>(o.faces(r, 2)));
  return ObjectModel::fromMesh(mesh, o.name);
}

HoldTrace traceGrasp(const TaskMapData& map, const HandModel& hand, std::size_t grasp,
                     const HoldTestOptions& options) {
  options.validate();
  checkHand(map, hand);
  if (grasp >= map.grasps.size())
    throw Error("validate: grasp " + std::to_string(grasp) + " is not in the map (it has " +
                std::to_string(map.grasps.size()) + " grasps, indices from 0)");
  const HoldTester tester(hand, mapObjectModel(map), options);
  const Eigen::VectorXd q = map.grasps.joints.row(static_cast<Eigen::Index>(grasp)).transpose();
  return tester.trace(map.grasps.poseAt(grasp), q);
}

ValidationSummary validateMap(TaskMapData* map, const HandModel& hand,
                              const ValidateOptions& options, const ValidateControl& control) {
  options.validate();
  control.validate();
  checkHand(*map, hand);
  ValidationSummary s;
  const HoldTester tester(hand, mapObjectModel(*map), options.hold);
  s.model = tester.info();
  const std::size_t n =
      options.grasps == 0 ? map->grasps.size() : std::min(options.grasps, map->grasps.size());
  const int threads = options.threads > 0
                          ? options.threads
                          : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<HoldResult> results;
  const double cpu0 = cpuSeconds();
  const auto wall0 = std::chrono::steady_clock::now();
  const bool complete = runTests(tester, *map, n, threads, &results, control);
  s.cpu_seconds = cpuSeconds() - cpu0;
  s.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  if (!complete) {
    s.status = ValidationSummary::Status::kInterrupted;
    s.message = "validation interrupted; the map is unchanged";
    return s;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const HoldResult& r = results[i];
    ++s.tested;
    s.holding += r.holds;
    ++s.statuses[holdStatusName(r.status)];
    if (r.status == HoldStatus::kSlipped)
      ++s.failed_by_direction[static_cast<std::size_t>(r.failed_direction)];
    if (map->grasps.force_closure[i]) {
      ++s.fc_tested;
      s.fc_holding += r.holds;
    }
    s.steps += r.steps;
  }
  map->validation = labels(results, map->grasps.size(), options.hold);
  if (!s.model.hand_dynamics.empty()) {  // an MJCF hand: which of its own dynamics were used
    auto params = nlohmann::ordered_json::parse(map->validation->params_json);
    params["hand_dynamics"] = nlohmann::ordered_json::parse(s.model.hand_dynamics);
    map->validation->params_json = params.dump();
  }
  s.message = std::to_string(s.holding) + " of " + std::to_string(s.tested) + " grasps hold";
  return s;
}

}  // namespace taskmap
