#pragma once
/// @file mesh_bvh.hpp
/// Private to the meshes stage: a bounding-volume hierarchy over a triangle mesh for ray
/// parity (inside tests) and closest-point queries. Immutable after construction; all
/// queries are const and thread-safe.

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/core/triangle_mesh.hpp"

namespace taskmap::detail {

/// Axis-aligned box tree with up to 4 triangles per leaf (median split of centroids).
class MeshBvh {
 public:
  /// Builds the tree; the mesh is copied.
  explicit MeshBvh(const TriangleMesh& mesh);

  /// Result of a ray parity query.
  enum class Parity { kInside, kOutside, kOnSurface, kAmbiguous };

  /// Winding number of the surface around p counted along the ray p + t d (t > 0): exits
  /// minus entries; kInside when positive. For a closed surface without self-intersections
  /// this is the crossing parity; overlapping closed shells are united. kAmbiguous when the
  /// ray grazes an edge or a vertex within a tolerance; kOnSurface when p lies on a triangle.
  Parity rayParity(const Eigen::Vector3d& p, const Eigen::Vector3d& d) const;

  /// True when p is strictly inside the closed mesh (ray winding over several fixed
  /// directions, generalized winding number as the fallback when all rays are ambiguous).
  bool contains(const Eigen::Vector3d& p) const;

  /// Distance from p to the closest surface point (metres); closest point and face on request.
  double closestPoint(const Eigen::Vector3d& p, Eigen::Vector3d* closest = nullptr,
                      int* face = nullptr) const;

  /// True when a triangle comes nearer p than r (metres): closestPoint's search with the bound
  /// r from the start, stopping at the first such triangle.
  bool within(const Eigen::Vector3d& p, double r) const;

  /// Nearest crossing of the ray p + t d (d unit) with a triangle for t in (t_min, t_max]:
  /// returns t and sets *face (original face index), or returns +infinity and sets -1. A ray
  /// through an edge or a vertex hits one of the triangles that share it (barycentric tolerance
  /// 1e-9), so a ray cannot slip between two triangles of a closed mesh.
  double firstHit(const Eigen::Vector3d& p, const Eigen::Vector3d& d, double t_min, double t_max,
                  int* face) const;

  /// Generalized winding number of the surface around p (1 inside, 0 outside), O(n).
  double windingNumber(const Eigen::Vector3d& p) const;

 private:
  struct Node {
    Eigen::Vector3d lo, hi;
    int left = -1, right = -1;  ///< children; -1 in a leaf
    int begin = 0, end = 0;     ///< triangle range in order_ for a leaf
  };
  int build(int begin, int end, std::vector<Eigen::Vector3d>& centroids);

  std::vector<Eigen::Vector3d> a_, b_, c_;  ///< triangle corners, in order_
  std::vector<int> order_;                  ///< original face index for each slot
  std::vector<Node> nodes_;
  double eps_ = 0;  ///< length tolerance: 1e-12 times the bounding box diagonal
};

}  // namespace taskmap::detail
