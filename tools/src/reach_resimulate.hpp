#pragma once
// `taskmap reach --map`: the final palm pose of a plan re-simulated by grasp_sim on the map's own
// hand and object, with the map's simulation and quality options (docs/REACHING.md
// "Re-simulation"). Lives in the tool: reaching does not depend on grasp_sim.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <optional>

#include <Eigen/Core>

#include "taskmap/core/pose.hpp"
#include "taskmap/mapstore/task_map_data.hpp"
#include "taskmap/validate/hold_test.hpp"

namespace taskmap::cli {

/// One grasp_sim trial from a planned palm pose, scored like the map's grasps.
struct Resimulation {
  std::string outcome;               ///< GraspStatus name ("ok", "no_palm_contact", ...)
  std::string message;               ///< the simulator's detail
  bool force_closure = false;        ///< of the re-simulated contacts
  double epsilon = 0.0;              ///< Ferrari-Canny epsilon (0 unless force closure)
  int contacts = 0;                  ///< pressed contacts
  std::vector<std::string> fingers;  ///< fingers in contact
  double retraction_m = 0.0;         ///< distance the simulator moved the palm out (+) or in (-)
  Pose start;                        ///< palm pose the trial started from (object frame)
  Pose final_pose;                   ///< palm pose after closing (object frame)
  Eigen::VectorXd joints;            ///< joints after closing (HandModel::jointNames() order)
  std::string hand_urdf;             ///< the hand file used
  /// The physics hold test of the re-simulated grasp (holdTestResimulated), when it ran.
  std::optional<HoldResult> hold;
};

/// The URDF of the map's hand: the path the build recorded (params_json "hand") when its SHA-256
/// matches the map's, else the bundled hand of the map's hand name with that SHA-256. Throws
/// Error naming the map's hand and what was tried when none matches.
std::string mapHandUrdf(const TaskMapData& map);

/// Re-simulates a grasp from `palm_in_object` (palm pose in the object frame, metres) with the
/// map's hand (mapHandUrdf), its object mesh and the simulation and quality options recorded in
/// params_json (defaults for keys a map does not record). Throws Error when the hand is not found.
Resimulation resimulateGrasp(const TaskMapData& map, const Pose& palm_in_object);

/// Runs the physics hold test (validate/hold_test.hpp, the protocol's defaults) on a
/// re-simulated grasp whose outcome is "ok": its final palm pose and joints, the map's hand
/// (r->hand_urdf) and the map's object; stores the result in r->hold. Does nothing otherwise.
void holdTestResimulated(const TaskMapData& map, Resimulation* r);

/// {outcome, message, force_closure, epsilon, contacts, fingers, retraction_m, start, final,
/// hand, and hold {holds, status, max_translation_m, max_rotation_rad, failed_direction} when
/// the hold test ran}.
nlohmann::json resimulationJson(const Resimulation& r);

}  // namespace taskmap::cli
