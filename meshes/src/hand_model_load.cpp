// HandModel::load: a short driver over the builder's steps (hand_model_build.hpp): URDF file,
// sidecar file (its "collision" options shape the collision meshes), URDF tree, sidecar keys,
// derived quantities.
#include "hand_model_build.hpp"

namespace taskmap {

HandModel HandModelBuilder::build(const std::string& urdf_path, const std::string& sidecar_arg) {
  HandModel h;
  const auto model = parseUrdfFile(h, urdf_path);
  const nlohmann::json js = readSidecar(h, sidecar_arg);
  readUrdfTree(h, *model,
               detail::collisionOptionsOf(js, "hand sidecar '" + h.sidecar_path_ + "': "));
  applySidecar(h, js);
  derive(h, js);
  return h;
}

HandModel HandModel::load(const std::string& urdf_path, const std::string& sidecar_arg) {
  return HandModelBuilder::build(urdf_path, sidecar_arg);
}

}  // namespace taskmap
