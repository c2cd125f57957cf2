#pragma once
/// @file mesh_parts.hpp
/// A mesh file (any format assimp reads) as its connected parts, in the file's frame: what a
/// hand's <mesh> collision element becomes before each part is cut into convex pieces
/// (convex_pieces.hpp). assimp parses in a bounded child process first (core's
/// bounded_child.hpp), so no file can crash or exhaust the caller.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/core/triangle_mesh.hpp"

namespace taskmap {

/// Reads mesh file `path` with assimp (triangulated, node transforms applied, then scaled by
/// `scale` per axis) and splits its faces into connected parts (vertices at the same position
/// are one, faces sharing a vertex are connected), in file order; identical points merged,
/// parts of fewer than 4 distinct vertices (stray edges, lone triangles) left out, so the
/// result may be empty. Messages name the file as "<what> '<path>'" (what: e.g. "URDF 'x':
/// link 'y': collision mesh"); throws Error when the path is not a regular file or the file is
/// unreadable, or when the bounded parse fails.
std::vector<TriangleMesh> loadMeshParts(const std::string& path, const Eigen::Vector3d& scale,
                                        const std::string& what);

}  // namespace taskmap
