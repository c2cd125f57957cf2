// Declared sizes of mesh files against their byte counts (mesh_bounds.hpp).
#include "mesh_bounds.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "taskmap/meshes/error.hpp"

namespace taskmap::detail {
namespace {

// Headers are read up to this many bytes (a PLY header with comments is a few KiB).
constexpr std::size_t kHeaderBytes = 64 * 1024;

std::string readHead(const std::string& path, std::size_t n) {
  std::ifstream in(path, std::ios::binary);
  std::string head(n, '\0');
  in.read(head.data(), static_cast<std::streamsize>(n));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head;
}

[[noreturn]] void refuse(const std::string& path, const std::string& what) {
  throw Error("mesh file '" + path + "': " + what);
}

// Parses a non-negative decimal count; false on anything else (signs, exponents, overflow).
bool parseCount(const std::string& token, std::uint64_t* out) {
  if (token.empty() || token.size() > 19) return false;
  std::uint64_t v = 0;
  for (char c : token) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
    v = v * 10 + static_cast<std::uint64_t>(c - '0');
  }
  *out = v;
  return true;
}

// need = sum of count * bytes_each, saturating; refuses when it exceeds available.
void requireFits(const std::string& path, const std::string& what, std::uint64_t count,
                 std::uint64_t bytes_each, std::uintmax_t available) {
  if (bytes_each == 0) bytes_each = 1;
  if (count > available / bytes_each)
    refuse(path, "header declares " + std::to_string(count) + " " + what + " (at least " +
                     std::to_string(bytes_each) + " bytes each) but the file has only " +
                     std::to_string(available) + " bytes for them (truncated or corrupt file)");
}

// ---- OFF: "[C][N][4]OFF" then "V F E" (comments start with #), one vertex and face per line.
void checkOff(const std::string& path, const std::string& head, std::uintmax_t size) {
  std::istringstream in(head);
  std::string line;
  std::vector<std::string> tokens;
  bool keyword = false;
  while (tokens.size() < 3 && std::getline(in, line)) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    for (std::string w; words >> w;) {
      if (!keyword) {
        keyword = true;
        // OFF, COFF, NOFF, STOFF, 4OFF...: the counts follow on the same or the next lines.
        if (w.size() >= 3 && w.compare(w.size() - 3, 3, "OFF") == 0) continue;
        refuse(path, "OFF file does not start with the OFF keyword");
      }
      tokens.push_back(w);
    }
  }
  std::uint64_t v = 0, f = 0;
  if (tokens.size() < 2 || !parseCount(tokens[0], &v) || !parseCount(tokens[1], &f))
    refuse(path, "OFF header has no valid vertex and face counts");
  // A vertex needs "x y z\n" (6 bytes), a face "3 a b c\n" (8 bytes).
  requireFits(path, "vertices", v, 6, size);
  requireFits(path, "faces", f, 8, size - v * 6);
}

// ---- PLY: header lines up to end_header; elements with scalar and list properties.
std::uint64_t plyTypeBytes(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

void checkPly(const std::string& path, const std::string& head, std::uintmax_t size) {
  const auto end = head.find("end_header");
  if (end == std::string::npos)
    refuse(path, "PLY header has no end_header within its first 64 KiB");
  const auto body_start = head.find('\n', end);
  const std::uintmax_t body =
      body_start == std::string::npos || body_start + 1 > size ? 0 : size - (body_start + 1);
  std::istringstream in(head.substr(0, end));
  std::string line, format;
  struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::uint64_t bytes = 0;  // minimal bytes of one element
  };
  std::vector<Element> elements;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "format") {
      words >> format;
    } else if (key == "element") {
      Element e;
      std::string count;
      words >> e.name >> count;
      if (!parseCount(count, &e.count)) refuse(path, "PLY element " + e.name + " has no count");
      elements.push_back(e);
    } else if (key == "property") {
      if (elements.empty()) refuse(path, "PLY property before any element");
      std::string type;
      words >> type;
      const bool binary = format != "ascii";
      if (type == "list") {
        std::string count_type;
        words >> count_type;
        if (plyTypeBytes(count_type) == 0) refuse(path, "PLY list with an unknown count type");
        elements.back().bytes += binary ? plyTypeBytes(count_type) : 2;
      } else {
        if (plyTypeBytes(type) == 0) refuse(path, "PLY property of unknown type '" + type + "'");
        elements.back().bytes += binary ? plyTypeBytes(type) : 2;
      }
    }
  }
  if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
    refuse(path, "PLY header has no valid format line");
  std::uintmax_t left = body;
  for (const Element& e : elements) {
    requireFits(path, "'" + e.name + "' elements", e.count, e.bytes, left);
    left -= e.count * std::max<std::uint64_t>(1, e.bytes);
  }
}

// ---- binary STL: 80-byte header, uint32 triangle count, 50 bytes per triangle.
bool looksLikeAsciiStl(const std::string& head) {
  if (head.compare(0, 5, "solid") != 0) return false;
  const std::string start = head.substr(0, 1024);
  return start.find("facet") != std::string::npos || start.find("endsolid") != std::string::npos;
}

void checkBinaryStl(const std::string& path, const std::string& head, std::uintmax_t size) {
  if (head.size() < 84) refuse(path, "binary STL shorter than its 84-byte header");
  std::uint64_t n = 0;
  for (int i = 3; i >= 0; --i) n = (n << 8) | static_cast<unsigned char>(head[80 + i]);
  requireFits(path, "triangles", n, 50, size - 84);
}

}  // namespace

void checkDeclaredSizes(const std::string& path, const std::string& ext, std::uintmax_t size) {
  if (size > kMaxMeshFileBytes)
    refuse(path, "file of " + std::to_string(size) + " bytes is larger than the limit of " +
                     std::to_string(kMaxMeshFileBytes) + " bytes");
  const std::string head = readHead(path, kHeaderBytes);
  std::string first;
  std::istringstream(head.substr(0, 64)) >> first;
  const bool off_keyword =
      first.size() >= 3 && first.size() <= 5 && first.compare(first.size() - 3, 3, "OFF") == 0;
  if (head.compare(0, 3, "ply") == 0) {
    checkPly(path, head, size);
  } else if (ext == "off" || off_keyword) {
    checkOff(path, head, size);
  } else if (ext == "stl" && !looksLikeAsciiStl(head)) {
    checkBinaryStl(path, head, size);
  }
}

}  // namespace taskmap::detail
