// The final grasp of a reach plan re-simulated by grasp_sim: the map's hand and object, its
// recorded simulation and quality options, one trial, scored with the map's centre of mass.
#include "reach_resimulate.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/grasp_sim/grasp_simulator.hpp"
#include "taskmap/quality/grasp_quality.hpp"
#include "taskmap/validate/validate_map.hpp"

namespace taskmap::cli {
namespace {

nlohmann::json mapParams(const TaskMapData& map) {
  try {
    const nlohmann::json j = nlohmann::json::parse(map.sampling.params_json);
    if (j.is_object()) return j;
  } catch (const nlohmann::json::exception&) {
    // A map whose params are not JSON (imported, hand-made): the defaults apply.
  }
  return nlohmann::json::object();
}

template <class T>
T param(const nlohmann::json& j, const char* key, T fallback) {
  const auto it = j.find(key);
  if (it == j.end() || it->is_null()) return fallback;
  try {
    return it->get<T>();
  } catch (const nlohmann::json::exception&) {
    throw Error(std::string("the map's build parameter '") + key + "' has the wrong type");
  }
}

/// Does the URDF at path hold the map's hand (same SHA-256)?
bool matchesHand(const std::string& path, const std::string& sha256) {
  if (path.empty() || !std::filesystem::is_regular_file(path)) return false;
  try {
    return HandModel::load(path).urdfSha256() == sha256;
  } catch (const Error&) {
    return false;
  }
}

GraspSimOptions simulationOptions(const nlohmann::json& p) {
  GraspSimOptions o;
  o.contact_tolerance = param(p, "contact_tolerance", o.contact_tolerance);
  o.max_retraction = param(p, "max_retraction", o.max_retraction);
  o.squeeze = param(p, "squeeze", o.squeeze);
  o.require_palm_contact = param(p, "require_palm_contact", o.require_palm_contact);
  const std::string mode = param(p, "grasp_mode", std::string());
  if (mode == "palm") o.grasp_mode = GraspMode::kPalm;
  if (mode == "fingertip") o.grasp_mode = GraspMode::kFingertip;
  o.standoff = param(p, "grasp_standoff", o.standoff);
  o.centre_coupled = param(p, "centre_coupled", o.centre_coupled);
  o.check_self_collision = param(p, "check_self_collision", o.check_self_collision);
  o.max_closing_steps = param(p, "max_closing_steps", o.max_closing_steps);
  o.validate();
  return o;
}

QualityOptions qualityOptions(const TaskMapData& map, const nlohmann::json& p) {
  QualityOptions o;
  o.friction = map.quality.friction;
  o.cone_edges = map.quality.cone_edges;
  o.contact_model = contactModelFromString(map.quality.contact_model);
  o.torsional_friction = param(p, "torsional_friction", o.torsional_friction);
  if (param(p, "wrench_norm", std::string("l1")) == "linf") o.norm = WrenchNorm::kLInf;
  o.volume = VolumeMode::kNever;
  o.validate();
  return o;
}

TriangleMesh objectMesh(const MapObject& object) {
  TriangleMesh mesh;
  const auto& v = object.vertices;
  for (Eigen::Index i = 0; i < v.rows(); ++i) mesh.vertices.emplace_back(v(i, 0), v(i, 1), v(i, 2));
  const auto& f = object.faces;
  for (Eigen::Index i = 0; i < f.rows(); ++i)
    mesh.faces.emplace_back(static_cast<int>(f(i, 0)), static_cast<int>(f(i, 1)),
                            static_cast<int>(f(i, 2)));
  return mesh;
}

nlohmann::json poseJson(const Pose& p) {
  const Eigen::Matrix<double, 7, 1> v = p.toVector7();
  return std::vector<double>(v.data(), v.data() + 7);
}

}  // namespace

std::string mapHandUrdf(const TaskMapData& map) {
  const std::string recorded = param(mapParams(map), "hand", std::string());
  if (matchesHand(recorded, map.hand.urdf_sha256)) return recorded;
  // A map built elsewhere (another checkout, the install tree): the bundled hand with that content.
  const std::filesystem::path hands = std::filesystem::path(dataDir()) / "hands";
  std::error_code ec;
  std::vector<std::string> candidates;
  for (const auto& entry : std::filesystem::directory_iterator(hands, ec)) {
    const std::string name = entry.path().filename().string();
    candidates.push_back((entry.path() / (name + ".urdf")).string());
  }
  std::sort(candidates.begin(), candidates.end());
  for (const std::string& urdf : candidates)
    if (matchesHand(urdf, map.hand.urdf_sha256)) return urdf;
  throw Error("cannot re-simulate: the map's hand '" + map.hand.name + "' (URDF SHA-256 " +
              map.hand.urdf_sha256.substr(0, 12) + "...) is neither at the recorded path '" +
              recorded + "' nor a bundled hand under " + hands.string() + "; pass --no-resimulate");
}

Resimulation resimulateGrasp(const TaskMapData& map, const Pose& palm_in_object) {
  const nlohmann::json params = mapParams(map);
  Resimulation r;
  r.hand_urdf = mapHandUrdf(map);
  r.start = palm_in_object;
  const HandModel hand = HandModel::load(r.hand_urdf);
  MeshLoadOptions load;
  load.repair = false;  // the map's mesh is the (already repaired) solid the grasps were made on
  const ObjectModel object = ObjectModel::fromMesh(objectMesh(map.object), map.object.name, load);
  const GraspSimulator simulator(object, hand, simulationOptions(params));
  const GraspResult g = simulator.simulate(palm_in_object);
  r.outcome = toString(g.status);
  r.message = g.message;
  r.final_pose = g.pose;
  r.joints = g.joints;
  r.fingers = g.fingers_in_contact;
  r.retraction_m = g.stats.retraction;
  r.contacts = static_cast<int>(g.contacts.size());
  if (g.status != GraspStatus::kOk) return r;
  const QualityResult q = evaluateGrasp(g.contacts, map.object.center_of_mass,
                                        map.object.torque_scale, qualityOptions(map, params));
  r.force_closure = q.force_closure;
  r.epsilon = q.epsilon;
  return r;
}

void holdTestResimulated(const TaskMapData& map, Resimulation* r) {
  if (r->outcome != "ok") return;
  const HoldTester tester(HandModel::load(r->hand_urdf), mapObjectModel(map));
  r->hold = tester.test(r->final_pose, r->joints);
}

nlohmann::json resimulationJson(const Resimulation& r) {
  nlohmann::json j = {{"outcome", r.outcome},
                      {"message", r.message},
                      {"force_closure", r.force_closure},
                      {"epsilon", r.epsilon},
                      {"contacts", r.contacts},
                      {"fingers", r.fingers},
                      {"retraction_m", r.retraction_m},
                      {"start", poseJson(r.start)},
                      {"final", poseJson(r.final_pose)},
                      {"hand", r.hand_urdf}};
  if (r.hold) {
    const HoldResult& h = *r.hold;
    j["hold"] = {
        {"holds", h.holds},
        {"status", holdStatusName(h.status)},
        {"max_translation_m", h.max_translation},
        {"max_rotation_rad", h.max_rotation},
        {"failed_direction",
         h.failed_direction < 0
             ? nlohmann::json(nullptr)
             : nlohmann::json(pushDirectionNames()[static_cast<std::size_t>(h.failed_direction)])}};
  }
  return j;
}

}  // namespace taskmap::cli
