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

/// Closest point to p on triangle abc (Ericson, Real-Time Collision Detection, 5.1.5).
Eigen::Vector3d closestOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b, const Eigen::Vector3d& c);

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

  /// True when p is strictly inside the closed mesh: the inside grid's label where p's cell
  /// holds no surface, else containsByRays(p). The same answer as containsByRays wherever
  /// that is the winding number (docs/METHOD.md §2, "Inside tests").
  bool contains(const Eigen::Vector3d& p) const;

  /// contains() by rays alone: ray winding over several fixed directions, the generalized
  /// winding number as the fallback when all rays are ambiguous.
  bool containsByRays(const Eigen::Vector3d& p) const;

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

  /// firstHit's answer (the same t and face), and in *again whether the ray crosses a triangle
  /// at some t in (t_hit + gap, t_max] (searched up to t_max (1 + 1e-9) + eps: a true answer
  /// may come from a crossing just past t_max, a false one is exact). One search of every box
  /// the ray meets within the range, without firstHit's nearest-first cut.
  double firstHitAndAgain(const Eigen::Vector3d& p, const Eigen::Vector3d& d, double t_min,
                          double t_max, double gap, int* face, bool* again) const;

  /// Generalized winding number of the surface around p (1 inside, 0 outside), O(n).
  double windingNumber(const Eigen::Vector3d& p) const;

 private:
  struct Node {
    Eigen::Vector3d lo, hi;
    int left = -1, right = -1;  ///< children; -1 in a leaf
    int begin = 0, end = 0;     ///< triangle range in order_ for a leaf
  };
  /// Whether the ray p + t d crosses the triangle at tree position i (not parallel to it,
  /// within its barycentric tolerance), and where: *t.
  bool rayCrosses(int i, const Eigen::Vector3d& p, const Eigen::Vector3d& d, double* t) const;
  /// Boxes of the triangles (unpadded), by face index: what a split's surface-area cost reads.
  struct TriangleBoxes {
    std::vector<Eigen::Vector3d> lo, hi;
  };
  int build(int begin, int end, const std::vector<Eigen::Vector3d>& centroids,
            const TriangleBoxes& boxes, int depth);
  /// The split of order_[begin, end) by the surface-area heuristic over binned centroids (their
  /// box [lo, hi]), its first index past the left part; -1 when no split separates them.
  int sahSplit(int begin, int end, const std::vector<Eigen::Vector3d>& centroids,
               const TriangleBoxes& boxes, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

  /// A regular grid over the root box (inside_grid.cpp): a cell whose bounding ball meets no
  /// triangle holds no surface point, so every point of it has the winding number of its
  /// centre, and 6-neighbouring such cells share it; one containsByRays() call labels each
  /// connected group of them. Cells the surface may cross are labelled kSurface.
  struct InsideGrid {
    enum Label : unsigned char { kUnknown = 0, kSurface = 1, kInside = 2, kOutside = 3 };
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< corner of cell (0, 0, 0), metres
    double cell = 0.0;                                 ///< cell edge, metres
    Eigen::Vector3i n = Eigen::Vector3i::Zero();       ///< cells per axis
    std::vector<unsigned char> label;                  ///< x fastest; empty: no grid
  };
  void buildInsideGrid();
  void markSurfaceCells();
  void labelFreeCells();
  /// The grid's label of p's cell, kUnknown when p is outside the grid.
  InsideGrid::Label gridLabel(const Eigen::Vector3d& p) const;

  std::vector<Eigen::Vector3d> a_, b_, c_;  ///< triangle corners, in order_
  std::vector<Eigen::Vector3d> e1_, e2_;    ///< edges b - a and c - a, in order_
  std::vector<double> n1_, n2_;             ///< their lengths, metres
  std::vector<int> order_;                  ///< original face index for each slot
  std::vector<Node> nodes_;
  double eps_ = 0;  ///< length tolerance: 1e-12 times the bounding box diagonal
  InsideGrid grid_;
};

}  // namespace taskmap::detail
