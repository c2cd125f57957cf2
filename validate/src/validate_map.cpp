// Labels a map's grasps with the hold test on worker threads. Steps: check the hand against
// the map, build the tester, test grasps in index order across threads (each result depends on
// its grasp only), summarise, store.
#include "taskmap/validate/validate_map.hpp"

#include <chrono>
#include <ctime>
#include <filesystem>
#include <memory>
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
  try {
    checkMapJoints(map);
  } catch (const Error& e) {
    throw Error(std::string("validate: ") + e.what());
  }
  if (hand.jointNames() != map.hand.joint_names)
    throw Error("validate: hand '" + hand.name() + "' (" + hand.urdfPath() +
                ") does not have the actuated joints of the map's hand '" + map.hand.name +
                "'; pass the hand the map was built with");
}

/// Runs `test` on grasps [0, n) on `threads` workers; results[i] is grasp i's.
template <typename Test>
bool runTests(const Test& test, const TaskMapData& map, std::size_t n, int threads,
              std::vector<RobustHoldResult>* results, const ValidateControl& control) {
  results->assign(n, RobustHoldResult{});
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
        (*results)[i] = test(map.grasps.poseAt(i), q);
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!failed.exchange(true)) error = "grasp " + std::to_string(i) + ": " + e.what();
        return;
      }
      holding += (*results)[i].nominal.holds ? 1 : 0;
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

}  // namespace

bool mapClosesFromOpen(const TaskMapData& map) {
  const auto params = nlohmann::json::parse(map.sampling.params_json, nullptr, false);
  if (!params.is_object()) return false;
  const auto it = params.find("hold_closing");
  return it != params.end() && it->is_string() && it->get<std::string>() == "from_open";
}

void checkMapJoints(const TaskMapData& map) {
  if (!map.hand.joint_names.empty() && map.grasps.joints.cols() > 0) return;
  throw Error("the map's grasps have no joint values (hand '" + map.hand.name +
              "': a map imported from ACRONYM without a hand stores poses only); import it again "
              "with `taskmap import --acronym FILE --object MESH --hand URDF` (a parallel-jaw "
              "gripper whose root link is ACRONYM's gripper base, e.g. the Franka hand), which "
              "closes the jaws at each pose and records the hand");
}

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
  j["close_from_open"] = s.close_from_open;
  j["cpu_seconds"] = s.cpu_seconds;
  j["wall_seconds"] = s.wall_seconds;
  j["grasps_per_cpu_second"] =
      s.cpu_seconds > 0 ? static_cast<double>(s.tested) / s.cpu_seconds : 0.0;
  j["steps"] = s.steps;
  if (!s.variant_failures.empty()) {
    j["robust"] = s.robust;
    j["robust_rate"] =
        s.tested ? static_cast<double>(s.robust) / static_cast<double>(s.tested) : 0.0;
    j["force_closure_robust"] = s.fc_robust;
    nlohmann::ordered_json v;
    for (const auto& [name, n] : s.variant_failures) v[name] = n;
    j["variant_failures"] = v;
  }
  return j.dump();
}

std::string holdParamsJson(const HoldTestOptions& o) {
  nlohmann::ordered_json j;
  j["object_mass"] = o.object_mass;
  j["sliding_friction"] = o.sliding_friction;
  j["torsional_friction"] = o.torsional_friction;
  j["timestep"] = o.timestep;
  j["integrator"] = integratorName(o.integrator);
  j["cone"] = "elliptic";
  j["impratio"] = o.impratio;
  j["noslip_iterations"] = o.noslip_iterations;
  j["solver_iterations"] = o.solver_iterations;
  j["solver_tolerance"] = o.solver_tolerance;
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
  j["close_from_open"] = o.close_from_open;
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
  j["object_max_faces"] = o.object_max_faces;
  j["settle_stop"] = o.settle_stop;
  if (o.settle_stop) {
    j["settle_window"] = o.settle_window;
    j["settle_joint_speed"] = o.settle_joint_speed;
    j["settle_envelope"] = o.settle_envelope;
  }
  if (o.margin_translation > 0.0) j["margin_translation"] = o.margin_translation;
  if (o.margin_rotation > 0.0) j["margin_rotation"] = o.margin_rotation;
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

void recordHandDynamics(const std::string& hand_dynamics, MapValidation* validation) {
  if (hand_dynamics.empty()) return;  // a URDF hand: the protocol's dynamics throughout
  auto params = nlohmann::ordered_json::parse(validation->params_json);
  params["hand_dynamics"] = nlohmann::ordered_json::parse(hand_dynamics);
  validation->params_json = params.dump();
}

MapValidation holdLabels(const std::vector<const RobustHoldResult*>& results,
                         const HoldTestOptions& protocol, const RobustHoldOptions* robust,
                         const std::vector<HoldVariant>& variants_run) {
  const std::size_t n = results.size();
  MapValidation v;
  v.hold.assign(n, MapValidation::kNotTested);
  v.status.assign(n, MapValidation::kNotTested);
  v.translation.assign(n, -1.0);
  v.rotation.assign(n, -1.0);
  v.direction.assign(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    if (!results[i]) continue;
    const HoldResult& r = results[i]->nominal;
    v.hold[i] = r.holds ? 1 : 0;
    v.status[i] = static_cast<std::uint8_t>(r.status);
    v.translation[i] = r.max_translation;
    v.rotation[i] = r.max_rotation;
    v.direction[i] = r.failed_direction;
  }
  v.protocol = "dexgraspbench_fc";
  v.engine = physicsEngine();
  v.params_json = holdParamsJson(protocol);
  if (!robust) return v;
  const std::size_t variants = variants_run.size();
  v.robust_json = robustParamsJson(*robust, variants_run);
  v.robust.assign(n, MapValidation::kNotTested);
  v.robust_share.assign(n, -1.0);
  v.push_translation.assign(n, -1.0);
  v.push_rotation.assign(n, -1.0);
  v.variant_held.assign(n * variants, MapValidation::kNotTested);
  for (std::size_t i = 0; i < n; ++i) {
    if (!results[i]) continue;
    const RobustHoldResult& r = *results[i];
    if (r.variant_held.size() != variants)
      throw Error("hold labels: grasp " + std::to_string(i) + " ran " +
                  std::to_string(r.variant_held.size()) + " variants, not the " +
                  std::to_string(variants) + " named");
    v.robust[i] = r.robust ? 1 : 0;
    v.robust_share[i] = r.share();
    v.push_translation[i] = r.push_translation;
    v.push_rotation[i] = r.push_rotation;
    std::copy(r.variant_held.begin(), r.variant_held.end(), v.variant_held.begin() + i * variants);
  }
  return v;
}

MapValidation subsetLabels(const MapValidation& v, const std::vector<std::size_t>& keep) {
  MapValidation out = v;
  auto pick = [&keep](const auto& from, auto* to) {
    to->clear();
    for (std::size_t i : keep) to->push_back(from[i]);
  };
  pick(v.hold, &out.hold);
  pick(v.status, &out.status);
  pick(v.translation, &out.translation);
  pick(v.rotation, &out.rotation);
  pick(v.direction, &out.direction);
  if (v.robust_json.empty()) return out;
  pick(v.robust, &out.robust);
  pick(v.robust_share, &out.robust_share);
  pick(v.push_translation, &out.push_translation);
  pick(v.push_rotation, &out.push_rotation);
  const std::size_t m = v.variantCount();
  out.variant_held.clear();
  for (std::size_t i : keep)
    out.variant_held.insert(out.variant_held.end(), v.variant_held.begin() + i * m,
                            v.variant_held.begin() + (i + 1) * m);
  return out;
}

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
  for (std::size_t k = 0; k < keep.size(); ++k)
    appendRow(in, keep[k], &out, static_cast<Eigen::Index>(k));
  MapValidation labels = subsetLabels(v, keep);
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
                     const HoldTestOptions& protocol) {
  HoldTestOptions options = protocol;
  options.close_from_open = options.close_from_open || mapClosesFromOpen(map);
  options.validate();
  checkHand(map, hand);
  if (grasp >= map.grasps.size())
    throw Error("validate: grasp " + std::to_string(grasp) + " is not in the map (it has " +
                std::to_string(map.grasps.size()) + " grasps, indices from 0)");
  const HoldTester tester(hand, mapObjectModel(map), options);
  const Eigen::VectorXd q = map.grasps.joints.row(static_cast<Eigen::Index>(grasp)).transpose();
  return tester.trace(map.grasps.poseAt(grasp), q);
}

namespace {

/// The summary's counts over the results of grasps [0, n).
void summarise(const std::vector<RobustHoldResult>& results, const TaskMapData& map,
               const RobustHoldTester* robust, ValidationSummary* s) {
  if (robust)
    for (const HoldVariant& v : robust->variants()) s->variant_failures.emplace_back(v.name(), 0);
  for (std::size_t i = 0; i < results.size(); ++i) {
    const HoldResult& r = results[i].nominal;
    ++s->tested;
    s->holding += r.holds;
    ++s->statuses[holdStatusName(r.status)];
    if (r.status == HoldStatus::kSlipped)
      ++s->failed_by_direction[static_cast<std::size_t>(r.failed_direction)];
    if (map.grasps.force_closure[i]) {
      ++s->fc_tested;
      s->fc_holding += r.holds;
    }
    s->steps += results[i].steps;
    if (!robust) continue;
    s->robust += results[i].robust;
    if (map.grasps.force_closure[i]) s->fc_robust += results[i].robust;
    // The nominal variant's entry counts protocol holds outside the margin; the others count
    // failures where the nominal variant held within it.
    const auto& held = results[i].variant_held;
    s->variant_failures[0].second += r.holds && held[0] == 0;
    if (held[0] != 1) continue;
    for (std::size_t k = 1; k < held.size(); ++k) s->variant_failures[k].second += held[k] == 0;
  }
}

}  // namespace

ValidationSummary validateMap(TaskMapData* map, const HandModel& hand, const ValidateOptions& asked,
                              const ValidateControl& control) {
  ValidateOptions options = asked;
  options.hold.close_from_open = options.hold.close_from_open || mapClosesFromOpen(*map);
  options.validate();
  control.validate();
  checkHand(*map, hand);
  ValidationSummary s;
  s.close_from_open = options.hold.close_from_open;
  const ObjectModel object = mapObjectModel(*map);
  std::unique_ptr<RobustHoldTester> robust;
  std::unique_ptr<HoldTester> tester;
  if (options.robust) {
    RobustHoldOptions ro = options.robust_variants;
    ro.hold = options.hold;
    ro.all_variants = true;
    ro.protocol_label = true;
    robust = std::make_unique<RobustHoldTester>(hand, object, ro);
    s.model = robust->nominal().info();
  } else {
    tester = std::make_unique<HoldTester>(hand, object, options.hold);
    s.model = tester->info();
  }
  const std::size_t n =
      options.grasps == 0 ? map->grasps.size() : std::min(options.grasps, map->grasps.size());
  const int threads = options.threads > 0
                          ? options.threads
                          : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::vector<RobustHoldResult> results;
  const double cpu0 = cpuSeconds();
  const auto wall0 = std::chrono::steady_clock::now();
  const auto test = [&](const Pose& palm, const Eigen::VectorXd& q) {
    if (robust) return robust->test(palm, q);
    RobustHoldResult r;
    r.nominal = tester->test(palm, q);
    r.steps = r.nominal.steps;
    return r;
  };
  const bool complete = runTests(test, *map, n, threads, &results, control);
  s.cpu_seconds = cpuSeconds() - cpu0;
  s.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  if (!complete) {
    s.status = ValidationSummary::Status::kInterrupted;
    s.message = "validation interrupted; the map is unchanged";
    return s;
  }
  summarise(results, *map, robust.get(), &s);
  std::vector<const RobustHoldResult*> tested(map->grasps.size(), nullptr);
  for (std::size_t i = 0; i < n; ++i) tested[i] = &results[i];
  map->validation = robust
                        ? holdLabels(tested, options.hold, &robust->options(), robust->variants())
                        : holdLabels(tested, options.hold);
  recordHandDynamics(s.model.hand_dynamics, &*map->validation);
  s.message = std::to_string(s.holding) + " of " + std::to_string(s.tested) + " grasps hold";
  if (robust) s.message += ", " + std::to_string(s.robust) + " robustly";
  return s;
}

}  // namespace taskmap
