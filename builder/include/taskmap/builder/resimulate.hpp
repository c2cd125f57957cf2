#pragma once
/// @file resimulate.hpp
/// A palm pose re-simulated by grasp_sim on a map's own hand and object, with the simulation and
/// quality options the map was built with (build_params.hpp; docs/REACHING.md
/// "Re-simulation"): `taskmap reach --map` checks the final grasp of a plan with it. Lives in
/// builder, the stage that reaches the simulator (reaching does not depend on grasp_sim).

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/core/pose.hpp"
#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap {

/// The physics hold test of a re-simulated grasp (the validate stage's protocol with its
/// defaults, docs/VALIDATION.md).
struct ResimulatedHold {
  bool holds = false;            ///< the object stayed within the limits under all six pushes
  std::string status;            ///< "holds", "penetration", "lost_in_closing", "slipped", ...
  double max_translation = 0.0;  ///< largest object displacement, metres
  double max_rotation = 0.0;     ///< largest object rotation, radians
  std::string failed_direction;  ///< push under which it failed ("-x" .. "+z"), "" if none
};

/// One grasp_sim trial from a given palm pose, scored like the map's grasps.
struct Resimulation {
  std::string outcome;                  ///< GraspStatus name ("ok", "no_palm_contact", ...)
  std::string message;                  ///< the simulator's detail
  bool force_closure = false;           ///< of the re-simulated contacts
  double epsilon = 0.0;                 ///< Ferrari-Canny epsilon (0 unless force closure)
  int contacts = 0;                     ///< pressed contacts
  std::vector<std::string> fingers;     ///< fingers in contact
  double retraction_m = 0.0;            ///< distance the simulator moved the palm out (+) or in (-)
  Pose start;                           ///< palm pose the trial started from (object frame)
  Pose final_pose;                      ///< palm pose after closing (object frame)
  Eigen::VectorXd joints;               ///< joints after closing (HandModel::jointNames() order)
  std::string hand_urdf;                ///< the hand file used
  std::optional<ResimulatedHold> hold;  ///< the hold test, when holdTestResimulated ran it
};

/// The URDF of the map's hand for re-simulation: findMapHandUrdf (mapstore/recorded_hand.hpp)
/// with the bundled hands (dataDir()/hands). Throws Error naming the map's hand and what was
/// tried, with the hint "pass --no-resimulate", when none matches.
std::string mapHandUrdf(const TaskMapData& map);

/// Re-simulates a grasp from `palm_in_object` (palm pose in the object frame, metres) with the
/// map's hand (mapHandUrdf), its object mesh and the simulation and quality options of its
/// build parameters (buildParamsFromJson: defaults for what a map does not record; friction,
/// cone edges and contact model from /quality). Throws Error when the hand is not found.
Resimulation resimulateGrasp(const TaskMapData& map, const Pose& palm_in_object);

/// Runs the physics hold test (the validator's protocol with its defaults) on a re-simulated
/// grasp whose outcome is "ok": its final palm pose and joints, the map's hand (r->hand_urdf)
/// and the map's object; stores the result in r->hold. Does nothing for other outcomes.
void holdTestResimulated(const TaskMapData& map, Resimulation* r);

/// The re-simulation as a JSON object (text), "resimulated" of `taskmap reach --map --json`:
/// {outcome, message, force_closure, epsilon, contacts, fingers, retraction_m, start, final
/// ([x y z qw qx qy qz], object frame, metres), hand, and hold {holds, status,
/// max_translation_m, max_rotation_rad, failed_direction (null if none)} when the hold test ran}.
std::string resimulationJson(const Resimulation& r);

/// The re-simulation as `taskmap reach --map` prints it: "re-simulated      <outcome>, force
/// closure | no force closure, epsilon E, N contacts (F fingers)" and, after a hold test,
/// "hold test         <status> (object moved M mm, turned D deg[, push <direction>])"; lines
/// end in '\n'.
std::string resimulationText(const Resimulation& r);

}  // namespace taskmap
