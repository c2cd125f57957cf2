#pragma once
// Private: the FLANN index over the 12-D pose embedding. FLANN stays in nn_index.cpp.

#include <cstddef>
#include <memory>
#include <vector>

namespace taskmap {
namespace detail {

/// A hit: point index (into the indexed rows) and SQUARED Euclidean distance.
struct IndexHit {
  std::size_t index;
  double distance2;
};

/// Nearest-neighbour index over row-major points (n x dim). The points must outlive the index.
/// Every query method is const and thread-safe (no shared mutable state).
class NnIndex {
 public:
  /// @param randomized false: exact single kd-tree. true: randomized forest of `trees` trees,
  /// nearest/knn visit at most `checks` leaves.
  NnIndex(const double* points, std::size_t n, int dim, bool randomized, int trees, int checks);
  ~NnIndex();
  NnIndex(const NnIndex&) = delete;
  NnIndex& operator=(const NnIndex&) = delete;

  std::size_t size() const { return n_; }
  /// k nearest (k <= size), nearest first, into out (resized).
  void knn(const double* query, std::size_t k, std::vector<IndexHit>& out) const;
  /// Every point with squared distance <= radius2, nearest first (exact in both modes).
  void radius(const double* query, double radius2, std::vector<IndexHit>& out) const;

 private:
  struct Flann;
  std::unique_ptr<Flann> flann_;
  std::size_t n_;
  int checks_;
};

}  // namespace detail
}  // namespace taskmap
