// A palm pose re-simulated by grasp_sim: the map's hand and object, its recorded simulation and
// quality options (build_params.hpp), one trial, scored with the map's centre of mass.
#include "taskmap/builder/resimulate.hpp"

#include "taskmap/builder/build_params.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/grasp_sim/grasp_simulator.hpp"
#include "taskmap/mapstore/recorded_hand.hpp"
#include "taskmap/quality/grasp_quality.hpp"
#include "taskmap/validate/hold_test.hpp"
#include "taskmap/validate/validate_map.hpp"

namespace taskmap {
namespace {

QualityOptions qualityOptions(const TaskMapData& map, const BuildParams& params) {
  QualityOptions o = params.options.quality;
  o.friction = map.quality.friction;
  o.cone_edges = map.quality.cone_edges;
  o.contact_model = contactModelFromString(map.quality.contact_model);
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

}  // namespace

std::string mapHandUrdf(const TaskMapData& map) {
  try {
    return findMapHandUrdf(map);
  } catch (const Error& e) {
    throw Error(std::string("cannot re-simulate: ") + e.what() + "; pass --no-resimulate");
  }
}

Resimulation resimulateGrasp(const TaskMapData& map, const Pose& palm_in_object) {
  const BuildParams params = buildParamsFromJson(map.sampling.params_json);
  Resimulation r;
  r.hand_urdf = mapHandUrdf(map);
  r.start = palm_in_object;
  const HandModel hand = HandModel::load(r.hand_urdf);
  MeshLoadOptions load;
  load.repair = false;  // the map's mesh is the (already repaired) solid the grasps were made on
  const ObjectModel object = ObjectModel::fromMesh(objectMesh(map.object), map.object.name, load);
  GraspSimOptions simulation = params.options.simulation;
  simulation.validate();
  const GraspSimulator simulator(object, hand, simulation);
  // A palm grasp is stored with the palm touching the surface, where a start a hair outside
  // and one a hair inside take different branches of the approach (advance or back out);
  // starting pressed in by the squeeze puts every start near it on one branch, the build's.
  Pose start = palm_in_object;
  if (simulation.grasp_mode.value_or(hand.graspMode()) == GraspMode::kPalm)
    start.position += hand.squeeze() * (start.orientation * hand.approachAxis());
  const GraspResult g = simulator.simulate(start);
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
  const HoldResult h = tester.test(r->final_pose, r->joints);
  ResimulatedHold out;
  out.holds = h.holds;
  out.status = holdStatusName(h.status);
  out.max_translation = h.max_translation;
  out.max_rotation = h.max_rotation;
  if (h.failed_direction >= 0)
    out.failed_direction = pushDirectionNames()[static_cast<std::size_t>(h.failed_direction)];
  r->hold = out;
}

}  // namespace taskmap
