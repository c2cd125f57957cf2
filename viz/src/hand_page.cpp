// The hand page's data: the hand model (viewer_hand.js poses it from the sliders).
#include "taskmap/viz/hand_page.hpp"

#include "hand_json.hpp"
#include "page.hpp"

namespace taskmap {

std::string handPageHtml(const HandModel& hand, const PageOptions& options) {
  options.validate();
  const nlohmann::json data = {{"kind", "hand"},
                               {"source", hand.urdfPath()},
                               {"hand", viz_detail::handJson(hand, options.decimals)}};
  const std::string title = options.title.empty() ? "taskmap hand: " + hand.name() : options.title;
  return viz_detail::assemblePage(title, "viewer_hand_js", data);
}

void writeHandPage(const HandModel& hand, const std::string& path, const PageOptions& options) {
  viz_detail::writePage(handPageHtml(hand, options), path);
}

}  // namespace taskmap
