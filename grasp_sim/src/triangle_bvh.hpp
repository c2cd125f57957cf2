#pragma once
// Private to grasp_sim: a bounding-volume hierarchy of axis-aligned boxes over the object's
// triangles (no Bullet). The culled link queries of CollisionScene walk it with their own node
// test (the link shape's k-DOP planes), which rejects far more than an axis-aligned box query.

#include <vector>

#include <Eigen/Core>

namespace taskmap {

class TriangleBvh {
 public:
  /// One node: its box; a leaf holds triangles [first, first + count) of order(), an inner node
  /// (count == 0) has children `first` and `first + 1`.
  struct Node {
    Eigen::Vector3d lo, hi;
    int first = 0;
    int count = 0;
  };

  /// Builds the tree over `faces` of `vertices` (median split on the widest centroid axis, at
  /// most kLeafSize triangles per leaf).
  TriangleBvh(const std::vector<Eigen::Vector3d>& vertices,
              const std::vector<Eigen::Vector3i>& faces);

  /// Calls `leaf(triangle)` for every triangle in a leaf whose node and ancestors all pass
  /// `accept(lo, hi)`. Depth-first, deterministic.
  template <class Accept, class Leaf>
  void visit(const Accept& accept, const Leaf& leaf) const {
    int stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[static_cast<std::size_t>(stack[--top])];
      if (!accept(n.lo, n.hi)) continue;
      if (n.count > 0) {
        for (int i = n.first; i < n.first + n.count; ++i) leaf(order_[static_cast<std::size_t>(i)]);
      } else {
        stack[top++] = n.first + 1;
        stack[top++] = n.first;
      }
    }
  }

  /// Maximum triangles per leaf.
  static constexpr int kLeafSize = 4;

 private:
  void build(int index, int begin, int end, int depth);
  std::vector<Node> nodes_;
  std::vector<int> order_;                  // triangle indexes, grouped by leaf
  std::vector<Eigen::Vector3d> centroid_;   // per triangle
  std::vector<Eigen::Vector3d> tlo_, thi_;  // per triangle box
};

}  // namespace taskmap
