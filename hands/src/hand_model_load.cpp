// HandModel::load: a short driver over the builder's steps (hand_model_build.hpp): URDF file,
// sidecar file (its "collision" options shape the collision meshes), URDF tree, sidecar keys,
// derived quantities.
#include <algorithm>

#include "hand_model_build.hpp"

namespace taskmap {

HandModel HandModelBuilder::build(const std::string& urdf_path, const std::string& sidecar_arg) {
  HandModel h;
  const auto model = parseUrdfFile(h, urdf_path);
  const nlohmann::json js = readSidecar(h, sidecar_arg);
  readUrdfTree(h, model,
               detail::collisionOptionsOf(js, "hand sidecar '" + h.sidecar_path_ + "': "));
  applySidecar(h, js);
  derive(h, js);
  return h;
}

HandModel HandModelBuilder::buildKinematics(const std::string& urdf_path) {
  HandModel h;
  const auto model = parseUrdfFile(h, urdf_path);
  readUrdfTree(h, model,
               detail::collisionOptionsOf(nlohmann::json::object(), "URDF '" + urdf_path + "': "));
  h.name_ = h.robot_name_;
  for (std::size_t l = 0; l < h.links_.size(); ++l)
    if (h.links_[l].parent_joint < 0) h.palm_link_ = static_cast<int>(l);
  h.preshape_.resize(static_cast<Eigen::Index>(h.actuated_.size()));
  for (std::size_t j = 0; j < h.actuated_.size(); ++j)
    h.preshape_[static_cast<Eigen::Index>(j)] = std::clamp(0.0, h.lower_[j], h.upper_[j]);
  return h;
}

HandModel HandModel::loadKinematics(const std::string& urdf_path) {
  return HandModelBuilder::buildKinematics(urdf_path);
}

HandModel HandModel::load(const std::string& urdf_path, const std::string& sidecar_arg) {
  return HandModelBuilder::build(urdf_path, sidecar_arg);
}

}  // namespace taskmap
