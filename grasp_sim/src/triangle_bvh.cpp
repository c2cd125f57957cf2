#include "triangle_bvh.hpp"

#include <algorithm>
#include <cassert>

namespace taskmap {

TriangleBvh::TriangleBvh(const std::vector<Eigen::Vector3d>& vertices,
                         const std::vector<Eigen::Vector3i>& faces) {
  const std::size_t n = faces.size();
  assert(n > 0);
  order_.resize(n);
  centroid_.resize(n);
  tlo_.resize(n);
  thi_.resize(n);
  for (std::size_t t = 0; t < n; ++t) {
    const auto& f = faces[t];
    const Eigen::Vector3d& a = vertices[static_cast<std::size_t>(f[0])];
    const Eigen::Vector3d& b = vertices[static_cast<std::size_t>(f[1])];
    const Eigen::Vector3d& c = vertices[static_cast<std::size_t>(f[2])];
    order_[t] = static_cast<int>(t);
    centroid_[t] = (a + b + c) / 3.0;
    tlo_[t] = a.cwiseMin(b).cwiseMin(c);
    thi_[t] = a.cwiseMax(b).cwiseMax(c);
  }
  nodes_.reserve(2 * n / kLeafSize + 2);
  nodes_.emplace_back();
  build(0, 0, static_cast<int>(n), 0);
  centroid_.clear();
  centroid_.shrink_to_fit();
}

// Fills node `index` and its subtree for order_[begin, end). Depth stays below the traversal
// stack (median splits: depth <= log2(n) + 1; capped at 60).
void TriangleBvh::build(int index, int begin, int end, int depth) {
  Eigen::Vector3d lo = tlo_[static_cast<std::size_t>(order_[static_cast<std::size_t>(begin)])];
  Eigen::Vector3d hi = thi_[static_cast<std::size_t>(order_[static_cast<std::size_t>(begin)])];
  Eigen::Vector3d clo =
      centroid_[static_cast<std::size_t>(order_[static_cast<std::size_t>(begin)])];
  Eigen::Vector3d chi = clo;
  for (int i = begin; i < end; ++i) {
    const auto t = static_cast<std::size_t>(order_[static_cast<std::size_t>(i)]);
    lo = lo.cwiseMin(tlo_[t]);
    hi = hi.cwiseMax(thi_[t]);
    clo = clo.cwiseMin(centroid_[t]);
    chi = chi.cwiseMax(centroid_[t]);
  }
  nodes_[static_cast<std::size_t>(index)].lo = lo;
  nodes_[static_cast<std::size_t>(index)].hi = hi;
  if (end - begin <= kLeafSize || depth >= 60) {
    nodes_[static_cast<std::size_t>(index)].first = begin;
    nodes_[static_cast<std::size_t>(index)].count = end - begin;
    return;
  }
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int x, int y) {
                     const double cx = centroid_[static_cast<std::size_t>(x)][axis];
                     const double cy = centroid_[static_cast<std::size_t>(y)][axis];
                     return cx < cy || (cx == cy && x < y);
                   });
  const int left = static_cast<int>(nodes_.size());
  nodes_[static_cast<std::size_t>(index)].first = left;
  nodes_[static_cast<std::size_t>(index)].count = 0;
  nodes_.emplace_back();
  nodes_.emplace_back();
  // Children are built depth-first into the two slots just reserved.
  build(left, begin, mid, depth + 1);
  build(left + 1, mid, end, depth + 1);
}

}  // namespace taskmap
