#pragma once
// URDFs for the hostile-input tests (issue 32): long chains, deep XML nesting, joints that do
// not form a tree. Written to files by the tests; shared by the hand (hands) and robot
// (reaching) front ends.
#include <cstddef>
#include <fstream>
#include <string>

namespace taskmap::testing {

/// A chain base -> l1 -> ... -> l<n> of revolute joints j1..jn (limits [-1, 1], box links).
inline std::string chainUrdf(std::size_t n) {
  std::string x = "<?xml version=\"1.0\"?>\n<robot name=\"chain\">\n";
  const std::string box =
      "<collision><geometry><box size=\"0.01 0.01 0.01\"/></geometry></collision>";
  x += "<link name=\"base\">" + box + "</link>\n";
  for (std::size_t i = 1; i <= n; ++i) {
    const std::string parent = i == 1 ? "base" : "l" + std::to_string(i - 1);
    const std::string child = "l" + std::to_string(i);
    x += "<link name=\"" + child + "\">" + box + "</link>\n";
    x += "<joint name=\"j" + std::to_string(i) + "\" type=\"revolute\"><parent link=\"" + parent +
         "\"/><child link=\"" + child +
         "\"/><origin xyz=\"0 0 0.01\"/><axis xyz=\"1 0 0\"/>"
         "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n";
  }
  return x + "</robot>\n";
}

/// The chain's hand sidecar: palm base, j1 closes, finger l1.
inline std::string chainSidecar() {
  return "{\"palm_link\": \"base\", \"approach_axis\": [0, 0, 1], \"preshape\": {\"j1\": 0.0},"
         " \"closing\": [{\"joint\": \"j1\", \"toward\": \"lower\", \"speed\": 1}],"
         " \"squeeze\": 0.001, \"fingers\": {\"a\": [\"l1\"]}}";
}

/// A valid robot whose XML nests depth elements inside one link (TinyXML recurses per level).
inline std::string deepUrdf(std::size_t depth) {
  std::string x = "<robot name=\"deep\"><link name=\"base\">";
  for (std::size_t i = 0; i < depth; ++i) x += "<a>";
  for (std::size_t i = 0; i < depth; ++i) x += "</a>";
  return x + "</link></robot>\n";
}

/// chainUrdf(2) plus links c1, c2 joined in a cycle (c1 -> c2 -> c1), attached to nothing.
inline std::string detachedCycleUrdf() {
  std::string x = chainUrdf(2);
  x.erase(x.rfind("</robot>"));
  const std::string box =
      "<collision><geometry><box size=\"0.01 0.01 0.01\"/></geometry></collision>";
  x += "<link name=\"c1\">" + box + "</link><link name=\"c2\">" + box + "</link>\n";
  x += "<joint name=\"k1\" type=\"fixed\"><parent link=\"c1\"/><child link=\"c2\"/></joint>\n";
  x += "<joint name=\"k2\" type=\"fixed\"><parent link=\"c2\"/><child link=\"c1\"/></joint>\n";
  return x + "</robot>\n";
}

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace taskmap::testing
