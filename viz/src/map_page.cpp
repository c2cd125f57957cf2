// The map page's data: object mesh, grasps (poses, joints, quality, contacts, clusters), the
// hand model and the optional hold labels; drawing happens in viewer_map.js.
#include "taskmap/viz/map_page.hpp"

#include <filesystem>

#include "hand_json.hpp"
#include "page.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

using viz_detail::flat;
using viz_detail::rounded;

nlohmann::json objectJson(const MapObject& o, int decimals) {
  return {{"name", o.name}, {"v", flat(o.vertices, decimals)}, {"f", viz_detail::flatInt(o.faces)}};
}

template <typename T>
nlohmann::json roundedList(const std::vector<T>& v, int decimals) {
  nlohmann::json out = nlohmann::json::array();
  for (const T& x : v) out.push_back(rounded(static_cast<double>(x), decimals));
  return out;
}

nlohmann::json graspsJson(const TaskMapData& map, int decimals) {
  const MapGrasps& g = map.grasps;
  nlohmann::json j = {{"n", g.size()},
                      {"pose", flat(g.pose, decimals)},
                      {"joints", flat(g.joints, decimals)},
                      {"fc", g.force_closure},
                      {"eps", roundedList(g.epsilon, decimals + 1)},
                      {"vol", g.volume},
                      {"off", g.contact_offsets},
                      {"cp", flat(g.contact_points, decimals)},
                      {"cn", flat(g.contact_normals, 3)},
                      {"cd", roundedList(g.contact_depths, decimals + 1)},
                      {"cl", g.contact_links},
                      {"contacts_available", g.contacts_available}};
  j["cluster"] = map.clustering ? nlohmann::json(map.clustering->labels) : nlohmann::json();
  return j;
}

nlohmann::json clustersJson(const TaskMapData& map) {
  nlohmann::json out = nlohmann::json::array();
  if (!map.clustering) return out;
  for (std::size_t k = 0; k < map.clustering->clusters.size(); ++k) {
    const ClusterSummary& c = map.clustering->clusters[k];
    out.push_back({{"id", k},
                   {"size", c.size},
                   {"rep", c.representative},
                   {"mean_eps", c.mean_epsilon},
                   {"best_eps", c.best_epsilon}});
  }
  return out;
}

/// One label per grasp from the physics hold test (HoldStatus names), null without one.
nlohmann::json holdJson(const TaskMapData& map) {
  if (!map.validation) return nullptr;
  static const char* const kStatus[] = {"holds", "penetration", "lost in closing", "slipped",
                                        "unstable"};
  nlohmann::json labels = nlohmann::json::array(), moved = nlohmann::json::array();
  const MapValidation& v = *map.validation;
  for (std::size_t i = 0; i < v.status.size(); ++i) {
    const std::uint8_t s = v.status[i];
    labels.push_back(s < 5 ? kStatus[s] : s == MapValidation::kNotTested ? "not tested" : "?");
    moved.push_back(viz_detail::rounded(v.translation[i], 5));
  }
  return {{"labels", labels}, {"translation", moved}, {"engine", v.engine}};
}

void checkInput(const MapPageInput& input) {
  if (input.map == nullptr) throw Error("map page: no map given");
  const TaskMapData& map = *input.map;
  if (input.hand != nullptr && input.hand->jointNames() != map.hand.joint_names)
    throw Error("map page: hand '" + input.hand->name() +
                "' has other actuated joints than the map's hand '" + map.hand.name + "'");
}

}  // namespace

std::string mapPageHtml(const MapPageInput& input, const PageOptions& options) {
  options.validate();
  checkInput(input);
  const TaskMapData& map = *input.map;
  const int d = options.decimals;
  nlohmann::json data = {
      {"kind", "map"},
      {"source", input.source},
      {"ghost_limit", options.ghost_limit},
      {"object", objectJson(map.object, d)},
      {"hand_name", map.hand.name},
      {"joint_names", map.hand.joint_names},
      {"link_names", map.hand.link_names},
      {"grasps", graspsJson(map, d)},
      {"clusters", clustersJson(map)},
      {"hand", input.hand != nullptr ? viz_detail::handJson(*input.hand, d) : nlohmann::json()},
      {"hold", holdJson(map)}};
  std::string title = options.title;
  if (title.empty())
    title = "taskmap: " + map.object.name + " x " + map.hand.name + " (" +
            std::to_string(map.grasps.size()) + " grasps)";
  return viz_detail::assemblePage(title, "viewer_map_js", data);
}

void writeMapPage(const MapPageInput& input, const std::string& path, const PageOptions& options) {
  viz_detail::writePage(mapPageHtml(input, options), path);
}

}  // namespace taskmap
