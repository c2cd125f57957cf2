// HandModel::load: a short driver over the builder's steps (hand_model_build.hpp): URDF tree,
// sidecar, derived quantities.
#include "hand_model_build.hpp"

namespace taskmap {

HandModel HandModelBuilder::build(const std::string& urdf_path, const std::string& sidecar_arg) {
  HandModel h;
  readUrdf(h, urdf_path);
  const nlohmann::json js = readSidecar(h, sidecar_arg);
  applySidecar(h, js);
  derive(h, js);
  return h;
}

HandModel HandModel::load(const std::string& urdf_path, const std::string& sidecar_arg) {
  return HandModelBuilder::build(urdf_path, sidecar_arg);
}

}  // namespace taskmap
