#pragma once
/// @file bounded_load.hpp
/// Private to the meshes stage: every mesh assimp reads (objects and hand link meshes) is parsed
/// in a forked child with memory and CPU limits (taskmap/core/bounded_child.hpp), so that no
/// file (a 3MF that makes assimp abort, a 141-byte .x declaring 250 million vertices, a zip
/// bomb) can crash or exhaust the calling process.

#include <string>

#include "mesh_soup.hpp"
#include "taskmap/core/bounded_child.hpp"

namespace taskmap::detail {

/// importMeshFile in a bounded child; the soup comes back over a pipe bit for bit.
MeshSoup importMeshFileBounded(const std::string& path, double scale, std::string* format);

}  // namespace taskmap::detail
