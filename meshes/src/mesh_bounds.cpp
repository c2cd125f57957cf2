// Declared sizes of mesh files against their byte counts (mesh_bounds.hpp).
#include "mesh_bounds.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "taskmap/core/error.hpp"

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

struct PlyProperty {
  bool list = false;
  std::uint64_t count_bytes = 0;  // list: size of the count
  bool count_signed = false;      // list: signed count type
  std::uint64_t bytes = 0;        // scalar: size; list: size of one item
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProperty> properties;
  // Minimal bytes of one element: binary sizes (lists empty), or 2 per value in ASCII.
  std::uint64_t minBytes(bool binary) const {
    std::uint64_t b = 0;
    for (const PlyProperty& p : properties) b += binary ? (p.list ? p.count_bytes : p.bytes) : 2;
    return std::max<std::uint64_t>(1, b);
  }
};

struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elements;
  std::size_t body = 0;  // offset of the first byte after end_header's line
};

PlyProperty plyProperty(const std::string& path, std::istringstream& words) {
  PlyProperty p;
  std::string type;
  words >> type;
  if (type == "list") {
    std::string count_type, item_type;
    words >> count_type >> item_type;
    p.list = true;
    p.count_bytes = plyTypeBytes(count_type);
    p.count_signed = !count_type.empty() && count_type[0] != 'u';
    p.bytes = plyTypeBytes(item_type);
    if (p.count_bytes == 0 || p.bytes == 0) refuse(path, "PLY list of an unknown type");
  } else {
    p.bytes = plyTypeBytes(type);
    if (p.bytes == 0) refuse(path, "PLY property of unknown type '" + type + "'");
  }
  return p;
}

PlyHeader plyHeader(const std::string& path, const std::string& head) {
  const auto end = head.find("end_header");
  if (end == std::string::npos)
    refuse(path, "PLY header has no end_header within its first 64 KiB");
  PlyHeader h;
  // assimp misparses (and may crash on) a body glued to end_header: a line break must follow.
  const std::size_t after = end + std::string("end_header").size();
  if (head.compare(after, 1, "\n") == 0) {
    h.body = after + 1;
  } else if (head.compare(after, 2, "\r\n") == 0) {
    h.body = after + 2;
  } else {
    refuse(path, "PLY end_header is not followed by a line break (truncated or corrupt file)");
  }
  std::istringstream in(head.substr(0, end));
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string key;
    words >> key;
    if (key == "format") {
      words >> h.format;
    } else if (key == "element") {
      PlyElement e;
      std::string count;
      words >> e.name >> count;
      if (!parseCount(count, &e.count)) refuse(path, "PLY element " + e.name + " has no count");
      h.elements.push_back(e);
    } else if (key == "property") {
      if (h.elements.empty()) refuse(path, "PLY property before any element");
      h.elements.back().properties.push_back(plyProperty(path, words));
    }
  }
  if (h.format != "ascii" && h.format != "binary_little_endian" && h.format != "binary_big_endian")
    refuse(path, "PLY header has no valid format line");
  return h;
}

[[noreturn]] void refuseList(const std::string& path, const PlyElement& e, std::uint64_t row,
                             const std::string& what) {
  refuse(path, "PLY " + e.name + " " + std::to_string(row) + ": " + what +
                   " (truncated or corrupt file)");
}

// Walks an ASCII body: every list count must be a plain integer no larger than the values
// left in the file (assimp reserves the count before reading the values).
void walkAsciiPly(const std::string& path, const PlyHeader& h, const std::string& bytes) {
  // assimp's ASCII PLY parser reads past a NUL byte (and crashes): text has none.
  const auto nul = bytes.find('\0', h.body);
  if (nul != std::string::npos)
    refuse(path, "ASCII PLY holds a NUL byte at offset " + std::to_string(nul) +
                     " (truncated or corrupt file)");
  std::size_t at = h.body;
  auto token = [&](std::string* out) {
    while (at < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
    const std::size_t start = at;
    while (at < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[at]))) ++at;
    *out = bytes.substr(start, at - start);
    return at > start;
  };
  std::string t;
  for (const PlyElement& e : h.elements)
    for (std::uint64_t row = 0; row < e.count; ++row)
      for (const PlyProperty& p : e.properties) {
        if (!token(&t)) return;  // truncated: assimp reports it
        if (!p.list) continue;
        std::uint64_t n = 0;
        if (!parseCount(t, &n)) refuseList(path, e, row, "list count '" + t + "' is not a count");
        if (n > (bytes.size() - at) / 2)
          refuseList(path, e, row, "list of " + t + " values, more than the file has bytes for");
        for (std::uint64_t k = 0; k < n; ++k)
          if (!token(&t)) return;
      }
}

// Walks a binary body the same way (counts read with their declared size and byte order).
void walkBinaryPly(const std::string& path, const PlyHeader& h, const std::string& bytes) {
  const bool little = h.format == "binary_little_endian";
  std::size_t at = h.body;
  for (const PlyElement& e : h.elements)
    for (std::uint64_t row = 0; row < e.count; ++row)
      for (const PlyProperty& p : e.properties) {
        if (!p.list) {
          at += p.bytes;
          continue;
        }
        if (at + p.count_bytes > bytes.size()) return;  // truncated: assimp reports it
        std::uint64_t n = 0;
        for (std::uint64_t i = 0; i < p.count_bytes; ++i) {
          const std::size_t k = little ? at + p.count_bytes - 1 - i : at + i;
          n = (n << 8) | static_cast<unsigned char>(bytes[k]);
        }
        at += p.count_bytes;
        if (p.count_signed && (n >> (8 * p.count_bytes - 1)) != 0)
          refuseList(path, e, row, "negative list count");
        if (n > (bytes.size() - at) / p.bytes)
          refuseList(path, e, row,
                     "list of " + std::to_string(n) + " values, more than the file has bytes for");
        at += n * p.bytes;
      }
}

void checkPly(const std::string& path, const std::string& head, std::uintmax_t size) {
  const PlyHeader h = plyHeader(path, head);
  const bool binary = h.format != "ascii";
  std::uintmax_t left = size > h.body ? size - h.body : 0;
  for (const PlyElement& e : h.elements) {
    requireFits(path, "'" + e.name + "' elements", e.count, e.minBytes(binary), left);
    left -= e.count * e.minBytes(binary);
  }
  // The counts fit: walk the body for list counts (assimp holds the whole file anyway).
  const std::string bytes = readHead(path, static_cast<std::size_t>(size));
  if (binary) {
    walkBinaryPly(path, h, bytes);
  } else {
    walkAsciiPly(path, h, bytes);
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
