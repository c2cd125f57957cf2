#include "taskmap/core/xml_scan.hpp"

#include <cctype>
#include <cstring>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

bool isNameChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-' || c == '.' ||
         c == ':';
}

// Position after the first occurrence of end at or after i (npos: none).
std::size_t skipPast(const std::string& xml, std::size_t i, const char* end) {
  const std::size_t at = xml.find(end, i);
  return at == std::string::npos ? at : at + std::strlen(end);
}

}  // namespace

XmlShape scanXml(const std::string& xml, int stop_depth) {
  XmlShape shape;
  int depth = 0;
  std::size_t i = 0;
  const std::size_t n = xml.size();
  while (i < n) {
    i = xml.find('<', i);
    if (i == std::string::npos) break;
    if (xml.compare(i, 4, "<!--") == 0) {
      i = skipPast(xml, i + 4, "-->");
    } else if (xml.compare(i, 9, "<![CDATA[") == 0) {
      i = skipPast(xml, i + 9, "]]>");
    } else if (xml.compare(i, 2, "<?") == 0) {
      i = skipPast(xml, i + 2, "?>");
    } else if (xml.compare(i, 2, "<!") == 0) {
      i = skipPast(xml, i + 2, ">");
    } else if (xml.compare(i, 2, "</") == 0) {
      if (depth > 0) --depth;
      i = skipPast(xml, i + 2, ">");
    } else {
      // Start tag: name, attributes (quoted values may hold '>'), then '>' or '/>'.
      std::size_t j = i + 1;
      while (j < n && isNameChar(xml[j])) ++j;
      const std::size_t name_length = j - i - 1;
      if (name_length == 4 && xml.compare(i + 1, 4, "link") == 0) ++shape.links;
      if (name_length == 5 && xml.compare(i + 1, 5, "joint") == 0) ++shape.joints;
      char quote = 0;
      bool self_closing = false;
      for (; j < n; ++j) {
        const char c = xml[j];
        if (quote != 0) {
          if (c == quote) quote = 0;
        } else if (c == '"' || c == '\'') {
          quote = c;
        } else if (c == '>') {
          self_closing = xml[j - 1] == '/';
          break;
        }
      }
      if (!self_closing && name_length > 0) {
        ++depth;
        if (depth > shape.max_depth) shape.max_depth = depth;
        if (depth > stop_depth) return shape;
      }
      i = j < n ? j + 1 : std::string::npos;
    }
  }
  return shape;
}

void checkUrdfShape(const std::string& xml, const std::string& what, const std::string& path,
                    std::size_t max_links) {
  const XmlShape s = scanXml(xml, kMaxUrdfDepth);
  const std::string W = what + " '" + path + "': ";
  if (s.max_depth > kMaxUrdfDepth)
    throw Error(W + "XML elements nested more than " + std::to_string(kMaxUrdfDepth) +
                " deep; refused before parsing (a URDF is a few levels deep)");
  if (s.links > max_links || s.joints > max_links)
    throw Error(W + std::to_string(s.links) + " links and " + std::to_string(s.joints) +
                " joints, more than the limit of " + std::to_string(max_links) +
                "; refused before parsing");
}

}  // namespace taskmap
