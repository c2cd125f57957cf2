// Batch queries: rows split into contiguous chunks, one per thread; each row is computed by
// the same code as the single query, so results do not depend on the thread count.
#include <algorithm>
#include <exception>
#include <thread>

#include "taskmap/core/error.hpp"
#include "taskmap/integration/task_map.hpp"

namespace taskmap {
namespace {

template <typename F>
void parallelRows(std::size_t n, int threads, F&& f) {
  std::size_t t = threads > 0 ? static_cast<std::size_t>(threads)
                              : std::max(1u, std::thread::hardware_concurrency());
  t = std::max<std::size_t>(1, std::min(t, n / 64 + 1));  // at least 64 rows per thread
  if (t == 1) {
    for (std::size_t i = 0; i < n; ++i) f(i);
    return;
  }
  std::vector<std::exception_ptr> errors(t);
  std::vector<std::thread> pool;
  pool.reserve(t);
  for (std::size_t k = 0; k < t; ++k) {
    pool.emplace_back([&, k] {
      try {
        const std::size_t lo = n * k / t, hi = n * (k + 1) / t;
        for (std::size_t i = lo; i < hi; ++i) f(i);
      } catch (...) {
        errors[k] = std::current_exception();
      }
    });
  }
  for (auto& th : pool) th.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
}

}  // namespace

BatchEvaluation TaskMap::evaluateBatch(const PoseRows& poses, std::optional<int> cluster) const {
  const std::vector<Pose> xs = posesFromRows(poses);
  const std::size_t n = xs.size();
  if (n > 0) evaluate(xs[0], cluster);  // cluster errors surface here, in the caller's thread
  BatchEvaluation out;
  const auto rows = static_cast<Eigen::Index>(n);
  out.proximity.resize(rows);
  out.proximity_gradient.resize(rows, 6);
  out.quality.resize(rows);
  out.quality_gradient.resize(rows, 6);
  out.quality_bound.resize(rows);
  out.nearest.resize(rows);
  out.nearest_distance.resize(rows);
  parallelRows(n, options().threads, [&](std::size_t i) {
    const Evaluation e = evaluate(xs[i], cluster);
    const auto r = static_cast<Eigen::Index>(i);
    out.proximity[r] = e.proximity.value;
    out.proximity_gradient.row(r) = e.proximity.gradient.transpose();
    out.quality[r] = e.quality.value;
    out.quality_gradient.row(r) = e.quality.gradient.transpose();
    out.quality_bound[r] = e.quality.value_bound;
    out.nearest[r] = static_cast<std::int64_t>(e.proximity.nearest.index);
    out.nearest_distance[r] = e.proximity.nearest.distance;
  });
  return out;
}

Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> TaskMap::nearestBatch(
    const PoseRows& poses, Eigen::VectorXd* distances, std::optional<int> cluster) const {
  const std::vector<Pose> xs = posesFromRows(poses);
  const std::size_t n = xs.size();
  if (n > 0) nearest(xs[0], cluster);
  Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> idx(static_cast<Eigen::Index>(n));
  Eigen::VectorXd dist(static_cast<Eigen::Index>(n));
  parallelRows(n, options().threads, [&](std::size_t i) {
    const Neighbor nb = nearest(xs[i], cluster);
    idx[static_cast<Eigen::Index>(i)] = static_cast<std::int64_t>(nb.index);
    dist[static_cast<Eigen::Index>(i)] = nb.distance;
  });
  if (distances) *distances = std::move(dist);
  return idx;
}

}  // namespace taskmap
