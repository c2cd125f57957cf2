// The only file that includes FLANN (it needs liblz4 and uses deprecated std:: parts).
#include "nn_index.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <mutex>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wshadow=local"
#include <flann/flann.hpp>
#pragma GCC diagnostic pop

namespace taskmap {
namespace detail {
namespace {

using Dist = flann::L2<double>;             // returns SQUARED distances
constexpr unsigned kForestSeed = 20080922;  // fixed: same map, same forest

// k nearest with a caller buffer; no allocation besides the output vector.
class KnnSet : public flann::ResultSet<double> {
 public:
  KnnSet(std::size_t k, std::vector<IndexHit>& out) : k_(k), out_(out) { out_.clear(); }
  bool full() const override { return out_.size() == k_; }
  double worstDist() const override {
    return full() ? out_.back().distance2 : std::numeric_limits<double>::max();
  }
  void addPoint(double dist, size_t index) override {
    if (full() && dist >= out_.back().distance2) return;
    // Insertion keeps out_ sorted by (distance, index): deterministic ties.
    IndexHit h{index, dist};
    auto pos =
        std::upper_bound(out_.begin(), out_.end(), h, [](const IndexHit& a, const IndexHit& b) {
          return a.distance2 < b.distance2 || (a.distance2 == b.distance2 && a.index < b.index);
        });
    if (full()) out_.pop_back();
    out_.insert(pos, h);
  }

 private:
  std::size_t k_;
  std::vector<IndexHit>& out_;
};

// Every point within radius2 (inclusive).
class RadiusSet : public flann::ResultSet<double> {
 public:
  RadiusSet(double radius2, std::vector<IndexHit>& out) : radius2_(radius2), out_(out) {
    out_.clear();
  }
  bool full() const override { return true; }
  // FLANN tests dist < worstDist(): nudge up so dist == radius2 counts as inside.
  double worstDist() const override {
    return std::nextafter(radius2_, std::numeric_limits<double>::max());
  }
  void addPoint(double dist, size_t index) override {
    if (dist <= radius2_) out_.push_back(IndexHit{index, dist});
  }

 private:
  double radius2_;
  std::vector<IndexHit>& out_;
};

}  // namespace

struct NnIndex::Flann {
  flann::Matrix<double> data;
  std::unique_ptr<flann::NNIndex<Dist>> index;            // nearest / knn
  std::unique_ptr<flann::KDTreeSingleIndex<Dist>> exact;  // radius (and knn when exact)
};

NnIndex::NnIndex(const double* points, std::size_t n, int dim, bool randomized, int trees,
                 int checks)
    : flann_(std::make_unique<Flann>()),
      n_(n),
      checks_(randomized ? checks : flann::FLANN_CHECKS_UNLIMITED) {
  if (n == 0) return;
  flann_->data = flann::Matrix<double>(const_cast<double*>(points), n, static_cast<size_t>(dim));
  // The exact tree serves radius searches in both modes (FLANN's forest would search its
  // first tree exactly, and complain on stderr about the others).
  flann_->exact = std::make_unique<flann::KDTreeSingleIndex<Dist>>(
      flann_->data, flann::KDTreeSingleIndexParams(8, !randomized));
  flann_->exact->buildIndex();
  if (randomized) {
    // FLANN's forest draws split dimensions from std::rand: seed it for reproducible trees
    // (under a lock, since rand's state is global).
    static std::mutex rand_mutex;
    std::lock_guard<std::mutex> lock(rand_mutex);
    flann::seed_random(kForestSeed);
    flann_->index =
        std::make_unique<flann::KDTreeIndex<Dist>>(flann_->data, flann::KDTreeIndexParams(trees));
    flann_->index->buildIndex();
  }
}

NnIndex::~NnIndex() = default;

void NnIndex::knn(const double* query, std::size_t k, std::vector<IndexHit>& out) const {
  k = std::min(k, n_);
  KnnSet set(k, out);
  if (k == 0) return;
  flann::SearchParams params(checks_);
  if (flann_->index) {
    flann_->index->findNeighbors(set, query, params);
  } else {
    flann_->exact->findNeighbors(set, query, params);
  }
}

void NnIndex::radius(const double* query, double radius2, std::vector<IndexHit>& out) const {
  RadiusSet set(radius2, out);
  if (n_ == 0) return;
  flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED);  // exact in both index kinds
  flann_->exact->findNeighbors(set, query, params);
  std::sort(out.begin(), out.end(), [](const IndexHit& a, const IndexHit& b) {
    return a.distance2 < b.distance2 || (a.distance2 == b.distance2 && a.index < b.index);
  });
}

}  // namespace detail
}  // namespace taskmap
