// Mesh writers: OBJ, STL (ASCII and binary), PLY, OFF.
#include "taskmap/meshes/mesh_io.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <Eigen/Geometry>

#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

std::string num(double v, int precision) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", precision, v);
  return buf;
}

Eigen::Vector3d faceNormal(const TriangleMesh& mesh, const Eigen::Vector3i& f) {
  const Eigen::Vector3d n =
      (mesh.vertices[f[1]] - mesh.vertices[f[0]]).cross(mesh.vertices[f[2]] - mesh.vertices[f[0]]);
  const double len = n.norm();
  return len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::UnitZ();
}

std::string objText(const TriangleMesh& mesh, const std::string& comment, int precision) {
  std::ostringstream out;
  if (!comment.empty()) {
    std::istringstream lines(comment);
    for (std::string line; std::getline(lines, line);) out << "# " << line << "\n";
  }
  for (const auto& v : mesh.vertices) {
    out << "v " << num(v.x(), precision) << " " << num(v.y(), precision) << " "
        << num(v.z(), precision) << "\n";
  }
  for (const auto& f : mesh.faces) {
    out << "f " << f[0] + 1 << " " << f[1] + 1 << " " << f[2] + 1 << "\n";
  }
  return out.str();
}

}  // namespace

void writeObj(const TriangleMesh& mesh, const std::string& path, const std::string& comment,
              int precision) {
  writeFileAtomically(path, objText(mesh, comment, precision),
                      "cannot write mesh file '" + path + "'");
}

void writeMesh(const TriangleMesh& mesh, const std::string& path, MeshFormat format,
               const std::string& comment) {
  constexpr int kDigits = 17;
  std::ostringstream out;
  switch (format) {
    case MeshFormat::kObj:
      writeObj(mesh, path, comment, kDigits);
      return;
    case MeshFormat::kStlAscii: {
      out << "solid taskmap\n";
      for (const auto& f : mesh.faces) {
        const Eigen::Vector3d n = faceNormal(mesh, f);
        out << "  facet normal " << num(n.x(), kDigits) << " " << num(n.y(), kDigits) << " "
            << num(n.z(), kDigits) << "\n    outer loop\n";
        for (int c = 0; c < 3; ++c) {
          const auto& v = mesh.vertices[f[c]];
          out << "      vertex " << num(v.x(), kDigits) << " " << num(v.y(), kDigits) << " "
              << num(v.z(), kDigits) << "\n";
        }
        out << "    endloop\n  endfacet\n";
      }
      out << "endsolid taskmap\n";
      break;
    }
    case MeshFormat::kStlBinary: {
      std::string bytes(80, '\0');
      const std::string header = comment.empty() ? "taskmap binary STL" : comment;
      std::memcpy(bytes.data(), header.data(), std::min<std::size_t>(header.size(), 79));
      auto put = [&](const void* p, std::size_t n) {
        bytes.append(static_cast<const char*>(p), n);
      };
      const auto count = static_cast<std::uint32_t>(mesh.faces.size());
      put(&count, 4);  // little-endian hosts only (x86-64, aarch64)
      for (const auto& f : mesh.faces) {
        const Eigen::Vector3d n = faceNormal(mesh, f);
        float values[12] = {float(n.x()), float(n.y()), float(n.z())};
        for (int c = 0; c < 3; ++c) {
          for (int k = 0; k < 3; ++k) values[3 + 3 * c + k] = float(mesh.vertices[f[c]][k]);
        }
        put(values, sizeof values);
        const std::uint16_t attributes = 0;
        put(&attributes, 2);
      }
      writeFileAtomically(path, bytes, "cannot write mesh file '" + path + "'");
      return;
    }
    case MeshFormat::kPly: {
      out << "ply\nformat ascii 1.0\n";
      if (!comment.empty()) out << "comment " << comment << "\n";
      out << "element vertex " << mesh.vertices.size()
          << "\nproperty double x\nproperty double y\nproperty double z\n"
          << "element face " << mesh.faces.size() << "\nproperty list uchar int vertex_indices\n"
          << "end_header\n";
      for (const auto& v : mesh.vertices) {
        out << num(v.x(), kDigits) << " " << num(v.y(), kDigits) << " " << num(v.z(), kDigits)
            << "\n";
      }
      for (const auto& f : mesh.faces) out << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
      break;
    }
    case MeshFormat::kOff: {
      out << "OFF\n";
      if (!comment.empty()) out << "# " << comment << "\n";
      out << mesh.vertices.size() << " " << mesh.faces.size() << " 0\n";
      for (const auto& v : mesh.vertices) {
        out << num(v.x(), kDigits) << " " << num(v.y(), kDigits) << " " << num(v.z(), kDigits)
            << "\n";
      }
      for (const auto& f : mesh.faces) out << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
      break;
    }
  }
  writeFileAtomically(path, out.str(), "cannot write mesh file '" + path + "'");
}

}  // namespace taskmap
