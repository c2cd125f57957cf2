#pragma once
// Private: the FLANN index over the 12-D pose embedding. FLANN stays in nn_index.cpp.

#include <cstddef>
#include <memory>
#include <vector>

namespace taskmap {
namespace detail {

/// A hit: point index (row of the indexed points) and SQUARED Euclidean distance.
struct IndexHit {
  std::size_t index;
  double distance2;
};

/// The index's squared Euclidean distance, bitwise: FLANN's L2 sums the squared differences
/// in groups of four ((d0^2 + d1^2 + d2^2 + d3^2) added to the running sum per group), then the
/// remainder one by one. A caller that re-tests the index's points against a radius or for the
/// nearest point (EvaluationSession, the ball tree's candidates) gets exactly the index's
/// distances and ties.
inline double squaredDistance(const double* a, const double* b, int dim) {
  double result = 0.0;
  int k = 0;
  for (; k + 3 < dim; k += 4) {
    const double d0 = a[k] - b[k], d1 = a[k + 1] - b[k + 1];
    const double d2 = a[k + 2] - b[k + 2], d3 = a[k + 3] - b[k + 3];
    result += d0 * d0 + d1 * d1 + d2 * d2 + d3 * d3;
  }
  for (; k < dim; ++k) {
    const double d = a[k] - b[k];
    result += d * d;
  }
  return result;
}

/// Nearest-neighbour index over n points of dim coordinates, row k at points + k * stride
/// (stride >= dim; the caller may keep more values per row after the coordinates). FLANN's
/// exact kd-tree, optionally with a randomized forest for approximate nearest/knn. The points
/// must outlive the index; the tree reads them in place (rows in leafOrder() give each leaf a
/// contiguous block of memory) or from its own reordered copy. Every query method is const and
/// thread-safe (no shared mutable state).
///
/// Ties in distance are broken by a key per row (`ids`, e.g. the grasp index): among points at
/// equal distance the one with the smaller key comes first.
class NnIndex {
 public:
  /// The order in which a full traversal of the exact tree over these points visits them:
  /// permuting the rows into this order makes every leaf of the tree over the permuted rows a
  /// contiguous block (the tree's splits depend on the point set, not on its order).
  static std::vector<std::size_t> leafOrder(const double* points, std::size_t n, int dim,
                                            std::size_t stride);

  /// @param ids tie-break key of each row, or null for the row index. Held by pointer.
  /// @param randomized false: exact single kd-tree. true: also a randomized forest of `trees`
  /// trees; nearest/knn visit at most `checks` of its leaves.
  /// @param reorder the exact tree keeps its own copy of the points in its leaf order (for rows
  /// not in leafOrder()); false: it reads the rows in place.
  NnIndex(const double* points, std::size_t n, int dim, std::size_t stride, const std::size_t* ids,
          bool randomized, int trees, int checks, bool reorder = false);
  ~NnIndex();
  NnIndex(const NnIndex&) = delete;
  NnIndex& operator=(const NnIndex&) = delete;

  std::size_t size() const { return n_; }
  /// The nearest point; size() > 0.
  IndexHit nearest(const double* query) const;
  /// k nearest (k <= size), nearest first, into out (resized).
  void knn(const double* query, std::size_t k, std::vector<IndexHit>& out) const;
  /// Every point with squared distance <= radius2, in traversal order (unsorted); exact in
  /// both modes.
  void radius(const double* query, double radius2, std::vector<IndexHit>& out) const;
  /// radius() and the nearest point from ONE traversal of the exact tree (its pruning bound is
  /// max(radius2, best so far)); out holds exactly what radius() returns, in the same order.
  /// With a randomized forest and no point within the radius, the nearest is the forest's
  /// (approximate) answer instead, as nearest() gives. size() > 0.
  IndexHit radiusAndNearest(const double* query, double radius2, std::vector<IndexHit>& out) const;

 private:
  struct Flann;
  std::unique_ptr<Flann> flann_;
  std::size_t n_;
  const std::size_t* ids_;
  int checks_;
};

}  // namespace detail
}  // namespace taskmap
