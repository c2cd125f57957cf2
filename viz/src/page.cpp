// The page skeleton shared by every view: scripts inlined, data as JSON, nothing fetched.
#include "page.hpp"

#include <cmath>

#include "resources.hpp"
#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {

void PageOptions::validate() const {
  if (decimals < 1 || decimals > 12)
    throw Error("page option decimals must be in [1, 12], got " + std::to_string(decimals));
  if (ghost_limit < 1)
    throw Error("page option ghost_limit must be >= 1, got " + std::to_string(ghost_limit));
}

bool viewerAvailable() {
  return !viz_detail::resource("three_js").empty();
}

namespace viz_detail {
namespace {

/// Text safe inside <script>: no "</" that could close the element early.
std::string scriptSafe(std::string text) {
  for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3))
    text.replace(at, 2, "<\\/");
  return text;
}

std::string htmlEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

std::string script(const std::string& body) {
  return "<script>\n" + body + "\n</script>\n";
}

}  // namespace

double rounded(double x, int decimals) {
  const double scale = std::pow(10.0, decimals);
  const double r = std::round(x * scale) / scale;
  return r == 0.0 ? 0.0 : r;  // no "-0.0"
}

nlohmann::json poseJson(const Pose& p, int decimals) {
  const Eigen::Quaterniond q = p.orientation.normalized();
  nlohmann::json out = nlohmann::json::array();
  for (double v : {p.position.x(), p.position.y(), p.position.z(), q.w(), q.x(), q.y(), q.z()})
    out.push_back(rounded(v, decimals + 2));
  return out;
}

std::string assemblePage(const std::string& title, const std::string& script_name,
                         const nlohmann::json& data) {
  if (!viewerAvailable())
    throw Error(
        "taskmap was built without three.js, so it cannot write interactive pages: install "
        "libjs-three (apt-get install libjs-three) and rebuild");
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += "<meta name=\"generator\" content=\"taskmap " TASKMAP_VERSION "\">\n";
  html += "<title>" + htmlEscape(title) + "</title>\n<style>\n" + resource("viewer_css") +
          "</style>\n</head>\n<body>\n";
  html += "<div id=\"tm-error\"></div>\n<div id=\"tm-app\"></div>\n";
  html += "<!-- three.js licence:\n" + resource("three_license") + "-->\n";
  html += script(scriptSafe(resource("three_js")));
  html += script(scriptSafe(resource("convex_hull_js")));
  html += script(scriptSafe(resource("convex_geometry_js")));
  html += script(scriptSafe(resource("orbit_controls_js")));
  html +=
      "<script type=\"application/json\" id=\"tm-data\">" + scriptSafe(data.dump()) + "</script>\n";
  html += script(scriptSafe(resource("viewer_common_js")));
  html += script(scriptSafe(resource(script_name)));
  html += "</body>\n</html>\n";
  return html;
}

void writePage(const std::string& html, const std::string& path) {
  writeFileAtomically(path, html, "cannot write page '" + path + "'");
}

}  // namespace viz_detail
}  // namespace taskmap
