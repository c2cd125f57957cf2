#pragma once
/// @file xml_scan.hpp
/// A cheap scan of XML bytes before a recursive parser sees them (TinyXML, under urdfdom,
/// recurses once per nesting level: 100,000 nested elements overflow the stack). Used by both
/// URDF front ends (hand models in meshes, robot models in reaching).

#include <cstddef>
#include <string>

namespace taskmap {

/// What the scan found.
struct XmlShape {
  int max_depth = 0;       ///< deepest element nesting (the root element is depth 1)
  std::size_t links = 0;   ///< start tags named "link"
  std::size_t joints = 0;  ///< start tags named "joint"
};

/// Nesting depth and link/joint counts of xml, in one linear pass without recursion (comments,
/// CDATA, processing instructions, declarations and quoted attribute values are skipped; stops
/// counting depth once it passes stop_depth).
XmlShape scanXml(const std::string& xml, int stop_depth = 1 << 20);

/// Deepest nesting a URDF may have (a URDF is 4-6 levels deep; xacro output the same).
constexpr int kMaxUrdfDepth = 64;
/// Most links (and most joints) a URDF may have: far more than any hand or arm, few enough that
/// loading stays well under a second.
constexpr std::size_t kMaxUrdfLinks = 4096;
/// Most links (and joints) a hand URDF may have: a hand model's derived data (link chains,
/// self-collision pairs) grows faster than linearly with its links (a 4096-link chain took
/// minutes); real hands have at most a few dozen.
constexpr std::size_t kMaxHandLinks = 256;

/// Throws Error("<what> '<path>': ...") naming the limit when xml nests deeper than
/// kMaxUrdfDepth or has more than max_links links or joints.
void checkUrdfShape(const std::string& xml, const std::string& what, const std::string& path,
                    std::size_t max_links = kMaxUrdfLinks);

}  // namespace taskmap
