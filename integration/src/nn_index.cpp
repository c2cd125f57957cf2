// The only file that includes FLANN (it needs liblz4 and uses deprecated std:: parts).
#include "nn_index.hpp"

#include <algorithm>
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
constexpr double kMax = std::numeric_limits<double>::max();
/// Points per leaf of the exact tree, chosen by measurement (tests/bench/integration, 1e5
/// samples, medians of 3 runs of evaluate p50 / p99 in us, mixed and near query sets):
/// 24: 15.2/748, 20.7/55; 32: 15.3/773, 19.5/40; 48: 14.6/630, 20.2/44; 64: 13.8/547, 19.8/39;
/// 96: 13.9/481, 19.6/35. The searches are bound by memory traffic: bigger leaves mean
/// contiguous scans and fewer node visits but more points scanned. p50 differences from 32 to
/// 96 are within run-to-run noise (about 10%); the mixed set's p99 (far queries, whose exact
/// nearest search visits much of the tree) falls with the leaf size.
constexpr int kLeafSize = 64;

// FLANN offers a point to a result set only if its distance is < worstDist(): returning the
// next double above a distance makes points at exactly that distance count (inclusive radius,
// deterministic ties by key).
double above(double d2) {
  return std::nextafter(d2, kMax);
}

// Tie-break key of row i.
struct Keys {
  const std::size_t* ids;
  std::size_t operator()(std::size_t i) const { return ids ? ids[i] : i; }
  bool less(const IndexHit& a, const IndexHit& b) const {
    return a.distance2 < b.distance2 ||
           (a.distance2 == b.distance2 && (*this)(a.index) < (*this)(b.index));
  }
};

// The nearest point only: no allocation, one comparison per offered point.
class NearestSet final : public flann::ResultSet<double> {
 public:
  explicit NearestSet(Keys keys) : keys_(keys) {}
  bool full() const override { return found_; }
  double worstDist() const override { return worst_; }
  void addPoint(double dist, size_t index) override {
    const IndexHit h{index, dist};
    if (found_ && !keys_.less(h, best_)) return;
    best_ = h;
    worst_ = above(dist);
    found_ = true;
  }
  const IndexHit& best() const { return best_; }

 private:
  Keys keys_;
  IndexHit best_{0, kMax};
  double worst_ = kMax;
  bool found_ = false;
};

// k nearest with a caller buffer; no allocation besides the output vector.
class KnnSet final : public flann::ResultSet<double> {
 public:
  KnnSet(std::size_t k, Keys keys, std::vector<IndexHit>& out) : k_(k), keys_(keys), out_(out) {
    out_.clear();
  }
  bool full() const override { return out_.size() == k_; }
  double worstDist() const override { return worst_; }
  void addPoint(double dist, size_t index) override {
    const IndexHit h{index, dist};
    if (full() && !keys_.less(h, out_.back())) return;
    // Insertion keeps out_ sorted by (distance, key): deterministic ties.
    auto pos =
        std::upper_bound(out_.begin(), out_.end(), h,
                         [this](const IndexHit& a, const IndexHit& b) { return keys_.less(a, b); });
    if (full()) out_.pop_back();
    out_.insert(pos, h);
    if (full()) worst_ = above(out_.back().distance2);
  }

 private:
  std::size_t k_;
  Keys keys_;
  std::vector<IndexHit>& out_;
  double worst_ = kMax;
};

// Every point within radius2 (inclusive), in traversal order.
class RadiusSet final : public flann::ResultSet<double> {
 public:
  RadiusSet(double radius2, std::vector<IndexHit>& out)
      : radius2_(radius2), worst_(above(radius2)), out_(out) {
    out_.clear();
  }
  bool full() const override { return true; }
  double worstDist() const override { return worst_; }
  void addPoint(double dist, size_t index) override {
    if (dist <= radius2_) out_.push_back(IndexHit{index, dist});
  }

 private:
  double radius2_, worst_;
  std::vector<IndexHit>& out_;
};

// Every point within radius2 and the nearest point, in one traversal: the pruning bound is
// max(radius2, best so far), so no subtree holding a point within the radius or closer than
// the best is skipped; before the first leaf it is unbounded (a nearest-neighbour descent).
class RadiusNearestSet final : public flann::ResultSet<double> {
 public:
  RadiusNearestSet(double radius2, Keys keys, std::vector<IndexHit>& out)
      : radius2_(radius2), radius_worst_(above(radius2)), keys_(keys), out_(out) {
    out_.clear();
  }
  bool full() const override { return true; }
  double worstDist() const override { return worst_; }
  void addPoint(double dist, size_t index) override {
    const IndexHit h{index, dist};
    if (dist <= radius2_) out_.push_back(h);
    if (found_ && !keys_.less(h, best_)) return;
    best_ = h;
    found_ = true;
    worst_ = std::max(radius_worst_, above(dist));
  }
  const IndexHit& best() const { return best_; }

 private:
  double radius2_, radius_worst_;
  Keys keys_;
  std::vector<IndexHit>& out_;
  IndexHit best_{0, kMax};
  double worst_ = kMax;
  bool found_ = false;
};

// Every point, in traversal order (leafOrder).
class AllSet final : public flann::ResultSet<double> {
 public:
  explicit AllSet(std::vector<std::size_t>& out) : out_(out) {}
  bool full() const override { return true; }
  double worstDist() const override { return kMax; }
  void addPoint(double, size_t index) override { out_.push_back(index); }

 private:
  std::vector<std::size_t>& out_;
};

flann::Matrix<double> matrix(const double* points, std::size_t n, int dim, std::size_t stride) {
  return flann::Matrix<double>(const_cast<double*>(points), n, static_cast<size_t>(dim),
                               stride * sizeof(double));
}

}  // namespace

struct NnIndex::Flann {
  // The exact tree reads the caller's rows in place when they are in leafOrder() (each leaf one
  // contiguous block, a hit's row in cache for the caller), else its own copy in leaf order.
  std::unique_ptr<flann::KDTreeSingleIndex<Dist>> exact;  // radius, and nearest/knn when exact
  std::unique_ptr<flann::NNIndex<Dist>> forest;           // nearest/knn when randomized
};

std::vector<std::size_t> NnIndex::leafOrder(const double* points, std::size_t n, int dim,
                                            std::size_t stride) {
  std::vector<std::size_t> order;
  if (n == 0) return order;
  order.reserve(n);
  flann::KDTreeSingleIndex<Dist> tree(matrix(points, n, dim, stride),
                                      flann::KDTreeSingleIndexParams(kLeafSize, false));
  tree.buildIndex();
  AllSet all(order);
  tree.findNeighbors(all, points, flann::SearchParams(flann::FLANN_CHECKS_UNLIMITED));
  return order;
}

NnIndex::NnIndex(const double* points, std::size_t n, int dim, std::size_t stride,
                 const std::size_t* ids, bool randomized, int trees, int checks, bool reorder)
    : flann_(std::make_unique<Flann>()),
      n_(n),
      ids_(ids),
      checks_(randomized ? checks : flann::FLANN_CHECKS_UNLIMITED) {
  if (n == 0) return;
  const flann::Matrix<double> data = matrix(points, n, dim, stride);
  // The exact tree serves radius searches in both modes (FLANN's forest would search its
  // first tree exactly, and complain on stderr about the others).
  flann_->exact = std::make_unique<flann::KDTreeSingleIndex<Dist>>(
      data, flann::KDTreeSingleIndexParams(kLeafSize, reorder));
  flann_->exact->buildIndex();
  if (randomized) {
    // FLANN's forest draws split dimensions from std::rand: seed it for reproducible trees
    // (under a lock, since rand's state is global).
    static std::mutex rand_mutex;
    std::lock_guard<std::mutex> lock(rand_mutex);
    flann::seed_random(kForestSeed);
    flann_->forest =
        std::make_unique<flann::KDTreeIndex<Dist>>(data, flann::KDTreeIndexParams(trees));
    flann_->forest->buildIndex();
  }
}

NnIndex::~NnIndex() = default;

IndexHit NnIndex::nearest(const double* query) const {
  NearestSet set(Keys{ids_});
  const flann::SearchParams params(checks_);
  if (flann_->forest) {
    flann_->forest->findNeighbors(set, query, params);
  } else {
    flann_->exact->findNeighbors(set, query, params);
  }
  return set.best();
}

void NnIndex::knn(const double* query, std::size_t k, std::vector<IndexHit>& out) const {
  k = std::min(k, n_);
  KnnSet set(k, Keys{ids_}, out);
  if (k == 0) return;
  const flann::SearchParams params(checks_);
  if (flann_->forest) {
    flann_->forest->findNeighbors(set, query, params);
  } else {
    flann_->exact->findNeighbors(set, query, params);
  }
}

void NnIndex::radius(const double* query, double radius2, std::vector<IndexHit>& out) const {
  RadiusSet set(radius2, out);
  if (n_ == 0) return;
  // Exact in both index kinds.
  flann_->exact->findNeighbors(set, query, flann::SearchParams(flann::FLANN_CHECKS_UNLIMITED));
}

IndexHit NnIndex::radiusAndNearest(const double* query, double radius2,
                                   std::vector<IndexHit>& out) const {
  if (flann_->forest) {
    // Keep the forest's contract: exact when the cut-off ball holds a point, else approximate.
    radius(query, radius2, out);
    if (out.empty()) return nearest(query);
    const Keys keys{ids_};
    return *std::min_element(out.begin(), out.end(),
                             [&](const IndexHit& a, const IndexHit& b) { return keys.less(a, b); });
  }
  RadiusNearestSet set(radius2, Keys{ids_}, out);
  flann_->exact->findNeighbors(set, query, flann::SearchParams(flann::FLANN_CHECKS_UNLIMITED));
  return set.best();
}

}  // namespace detail
}  // namespace taskmap
