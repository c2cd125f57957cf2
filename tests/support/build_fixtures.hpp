#pragma once
// The small build every builder test and benchmark runs: the 4 x 5 x 12 cm box with the
// Franka gripper (meshes/hands/panda/). Needs TASKMAP_HANDS_DIR.
#include <string>

#include "taskmap/meshes/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"
#include "test_meshes.hpp"

namespace taskmap::testing {

/// The 4 x 5 x 12 cm box, loaded once.
inline const ObjectModel& boxObject() {
  static const ObjectModel object = ObjectModel::fromMesh(makeBox(0.04, 0.05, 0.12), "box");
  return object;
}

/// The bundled Franka gripper, loaded once.
inline const HandModel& pandaHand() {
  static const HandModel hand =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/panda/panda.urdf");
  return hand;
}

}  // namespace taskmap::testing
