#pragma once
/// @file hand_info.hpp
/// What `taskmap hand-info` reports about a hand (URDF + sidecar): joints, limits, mimic
/// couplings, preshape and closing, palm frame, approach axis, rho, reach, fingers, collision
/// meshes, and the warnings and notes of checkHand; as JSON text and as the printed text.

#include <string>

#include "taskmap/hands/hand_model.hpp"
#include "taskmap/inspect/hand_check.hpp"

namespace taskmap {

/// What handInfo reports on.
struct HandInfoOptions {
  std::string hand;  ///< URDF of the hand (its <stem>.hand.json sidecar beside it)
  /// Throws Error("hand '<hand>' does not exist; give a hand URDF") when hand is not a file.
  void validate() const;
};

/// The report of one hand.
struct HandInfo {
  /// kOk: the hand can grasp as far as checkHand can tell; kWarnings: report.warnings names
  /// set-ups that cannot grasp.
  enum class Status { kOk, kWarnings };
  Status status = Status::kOk;  ///< see Status
  std::string message;          ///< the first warning, or empty
  HandReport report;            ///< checkHand's warnings and notes
  /// JSON text indented by 2 (what `hand-info --json` prints, without the final newline): name,
  /// robot_name, urdf, sidecar, urdf_sha256, joints[{name, type, parent, child, [lower, upper,
  /// axis (joint frame), mimic {joint, multiplier, offset} | actuated, preshape, closed]}],
  /// closing[{joint, target, speed}], palm_link, palm_frame {xyz (m), rpy (rad)} in the palm
  /// link, root_to_palm {xyz, rpy} in the URDF root, approach_axis (palm frame), rotation_scale
  /// (m/rad), reach (m), squeeze, fingers {name: [links]}, links[{name, shapes, palm, finger}],
  /// collision_meshes[{link, file, part, faces, pieces, decomposed, wrapped, raw_pieces,
  /// mesh_volume, hull_volume, pieces_volume (m^3), note}], warnings, notes.
  std::string json;
  std::string text;  ///< the text `hand-info` prints (lines ending in newlines)
};

/// Reports on a loaded hand (a few forward-kinematics passes: milliseconds).
HandInfo handInfo(const HandModel& hand);

/// Loads options.hand (validated) and reports on it. Throws Error naming the file when the
/// hand does not load.
HandInfo handInfo(const HandInfoOptions& options);

}  // namespace taskmap
