#pragma once
/// @file mesh_io.hpp
/// Writing triangle meshes to common formats (for reference objects, tests and export).
/// Every writer writes a temporary file next to the target and renames it into place.

#include <string>

#include "taskmap/core/triangle_mesh.hpp"

namespace taskmap {

/// Mesh file formats we write.
enum class MeshFormat {
  kObj,        ///< Wavefront OBJ, 1-based indices
  kStlAscii,   ///< STL, ASCII ("solid ... endsolid")
  kStlBinary,  ///< STL, binary (80-byte header, float32 coordinates)
  kPly,        ///< PLY, ASCII, vertex + face elements
  kOff,        ///< OFF (Object File Format)
};

/// Writes `mesh` (metres) to `path`. Coordinates are written with 17 significant digits
/// (float32 for binary STL). `comment` goes into the header where the format has one.
/// Throws Error naming the file when it cannot be written.
void writeMesh(const TriangleMesh& mesh, const std::string& path, MeshFormat format,
               const std::string& comment = "");

/// Writes `mesh` as OBJ with `precision` significant digits (the reference objects use 9:
/// sub-nanometre rounding, small files). Throws Error naming the file on failure.
void writeObj(const TriangleMesh& mesh, const std::string& path, const std::string& comment,
              int precision);

}  // namespace taskmap
