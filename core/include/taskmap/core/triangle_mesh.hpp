#pragma once
/// @file triangle_mesh.hpp
/// A plain indexed triangle mesh in metres.

#include <vector>

#include <Eigen/Core>

namespace taskmap {

/// Indexed triangle mesh. Vertices in metres in the object frame; faces index vertices,
/// counter-clockwise seen from outside (outward normals by the right-hand rule).
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;  ///< metres
  std::vector<Eigen::Vector3i> faces;     ///< vertex indices, outward orientation
};

}  // namespace taskmap
