#pragma once
// Private: the mixture terms of one query, collected and then summed with one batched exp.

#include <cstddef>
#include <vector>

#include "kernels.hpp"
#include "vector_exp.hpp"

namespace taskmap {
namespace detail {

/// Terms of a quality mixture for one query: their embedding differences, weights and kernel
/// distances, summed by flushInto() with the exps computed together (expBatch). The sums are
/// addMixtureDifference's, term by term and in order, except for the exp (libmvec's, within
/// 4 ulp). Reused per thread (termBatch()): a query allocates nothing once it has grown.
class TermBatch {
 public:
  /// Room for n more terms.
  void reserve(std::size_t n) {
    if (diffs_.size() < (size_ + n) * kEmbeddingDim) {
      diffs_.resize((size_ + n) * kEmbeddingDim);
      weights_.resize(size_ + n);
      exps_.resize(size_ + n);
    }
  }
  /// Where the next term's differences x_i - x (12 doubles) go; reserve() first.
  double* nextDiff() { return diffs_.data() + size_ * kEmbeddingDim; }
  /// Keeps the term whose differences are at nextDiff(): weight w > 0, Mahalanobis distance d.
  void commit(double w, double d) {
    weights_[size_] = w;
    exps_[size_] = d < kKernelUnderflow ? -0.5 * d : -kHuge;  // exp(-kHuge) = 0 exactly
    ++size_;
  }
  /// Adds the kept terms to m in order and empties the batch.
  void flushInto(MixtureSum& m) {
    expBatch(exps_.data(), exps_.data(), size_);
    addMixtureExps(diffs_.data(), weights_.data(), exps_.data(), size_, m);
    size_ = 0;
  }
  std::size_t size() const { return size_; }

 private:
  static constexpr double kHuge = 1e300;
  std::vector<double> diffs_, weights_, exps_;
  std::size_t size_ = 0;
};

/// The calling thread's batch (empty between queries).
inline TermBatch& termBatch() {
  thread_local TermBatch batch;
  return batch;
}

}  // namespace detail
}  // namespace taskmap
