#pragma once
// The files embedded at build time (viz/cmake/embed_resources.cmake): three.js and its convex
// hull and orbit controls, its licence, and the viewer's own CSS and scripts (viz/resources).

#include <string>

namespace taskmap::viz_detail {

/// The bytes of an embedded file by name (three_js, viewer_css, ...), "" when it was absent.
std::string resource(const std::string& name);

}  // namespace taskmap::viz_detail
