#pragma once
// HandModelBuilder: the steps of HandModel::load (private to hands). The driver in
// hand_model_load.cpp runs them in order: URDF file, sidecar file (hand_model_sidecar.cpp), URDF
// tree with collision meshes (hand_model_urdf.cpp), sidecar keys, derived quantities
// (hand_model_derived.cpp).
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "collision_mesh.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/hands/urdf_model.hpp"

namespace taskmap {

/// Bytes of the file at `path`; throws Error "cannot read <what> '<path>'" when unreadable.
std::string readHandFile(const std::string& path, const char* what);

/// Builds a HandModel step by step; each step reads and writes the model's private fields.
struct HandModelBuilder {
  /// Loads the URDF and its sidecar into a complete model (HandModel::load).
  static HandModel build(const std::string& urdf_path, const std::string& sidecar_arg);
  /// The URDF tree alone (HandModel::loadKinematics).
  static HandModel buildKinematics(const std::string& urdf_path);

  // ---- URDF tree (hand_model_urdf.cpp) ----
  /// Reads and parses the URDF: path, SHA-256, robot name; checks it has a root link.
  static UrdfModel parseUrdfFile(HandModel& h, const std::string& urdf_path);
  /// Links (collision meshes converted with `options`) and joints depth-first, actuated
  /// joints, mimic chains resolved to their driver.
  static void readUrdfTree(HandModel& h, const UrdfModel& model,
                           const detail::CollisionOptions& options);

  // ---- Sidecar (hand_model_sidecar.cpp) ----
  /// Reads <sidecar> (default <urdf dir>/<stem>.hand.json), checks its keys, returns the JSON.
  static nlohmann::json readSidecar(HandModel& h, const std::string& sidecar_arg);
  /// Palm link and frame, approach axis, preshape, closing motion, squeeze, fingers.
  static void applySidecar(HandModel& h, const nlohmann::json& js);

  // ---- Derived quantities (hand_model_derived.cpp) ----
  /// Palm-rigid links, root-to-palm transform, link drivers, joint levers, reach and rotation
  /// scale (the sidecar's rotation_scale overrides the measured one).
  static void derive(HandModel& h, const nlohmann::json& js);
};

}  // namespace taskmap
