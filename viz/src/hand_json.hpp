#pragma once
// A hand model as the viewer draws it: links with their convex shapes, the joint tree with
// mimic couplings and limits (the page repeats HandModel::linkPoses), palm frame, approach.

#include <nlohmann/json.hpp>

#include "taskmap/hands/hand_model.hpp"

namespace taskmap::viz_detail {

/// {name, joint_names, lower, upper, preshape, closed, approach, root_to_palm, palm_link,
/// links [{name, palm, finger, shapes [{t, o, s | r, l | p}]}], joints [{t, parent, child, o,
/// axis, d, m, off}]}; poses as x y z qw qx qy qz, lengths rounded to `decimals`.
nlohmann::json handJson(const HandModel& hand, int decimals);

/// The closed configuration: each closing joint at its target, the others at the preshape.
Eigen::VectorXd closedJoints(const HandModel& hand);

}  // namespace taskmap::viz_detail
