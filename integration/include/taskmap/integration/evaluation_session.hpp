#pragma once
/// @file evaluation_session.hpp
/// A warm-started TaskMap::evaluate for one optimizer run (issue 7 follow-up). A reaching
/// optimizer evaluates poses that move a little from one iteration to the next (docs/METHOD.md
/// §3); the session keeps the samples within R = cutoffRadius() + margin of an anchor pose and
/// answers queries near the anchor from that cache instead of searching the index.
///
/// Exactness: the results equal TaskMap::evaluate(x, cluster) (same nearest sample and
/// distance, same mixture terms; value and gradients up to summation order). With delta the
/// embedding distance from the anchor a to x and delta <= margin, every sample within the
/// cut-off of x is within cut-off + delta <= R of a, so it is cached (triangle inequality);
/// the best cached sample at distance d* is the exact nearest when d* < R - delta, since every
/// uncached sample is farther than R - delta from x. Otherwise the session searches the index
/// again around x (a new anchor). In QualityMode::kExact the session calls TaskMap::evaluate.
///
/// Threads: a session is NOT thread-safe (it changes its cache on every call); use one
/// session per optimizer thread. Many sessions may share one TaskMap, whose const methods
/// stay thread-safe.

#include <cstddef>
#include <memory>
#include <optional>

#include "taskmap/core/pose.hpp"
#include "taskmap/integration/task_map.hpp"

namespace taskmap {

/// Counters of an EvaluationSession since construction or reset().
struct SessionStats {
  std::size_t calls = 0;      ///< evaluate() calls
  std::size_t anchors = 0;    ///< index searches that (re)filled the cache (first call included)
  std::size_t fallbacks = 0;  ///< anchors forced because the cached nearest was not certified
};

/// Cached evaluation of poses near each other; see the file comment for the contract.
class EvaluationSession {
 public:
  /// Default margin as a fraction of TaskMap::cutoffRadius(), chosen by measurement on
  /// optimizer trajectories (tests/bench/integration/integration_bench.cpp, where the sweep is
  /// recorded): 0.25 has the lowest p50 and, of the margins that reuse the cache, the lowest
  /// p99 (smaller refills).
  static constexpr double kDefaultMarginFactor = 0.25;

  /// @param map the task map; it must outlive the session (held by reference).
  /// @param cluster restrict to one cluster's samples (0..K-1), as TaskMap::evaluate.
  /// @param margin how far (pose/embedding distance, metres, finite, >= 0) a query may move
  /// from the anchor before the cache is refilled; default kDefaultMarginFactor *
  /// map.cutoffRadius(). Larger margins refill less often but scan more cached samples.
  /// Throws Error for an invalid margin or cluster, or an empty cluster.
  explicit EvaluationSession(const TaskMap& map, std::optional<int> cluster = std::nullopt,
                             std::optional<double> margin = std::nullopt);
  /// Moves the cache and stats; the moved-from session may only be destroyed or assigned to.
  EvaluationSession(EvaluationSession&&) noexcept;
  /// Moves the cache and stats (as the move constructor).
  EvaluationSession& operator=(EvaluationSession&&) noexcept;
  /// Releases the cache.
  ~EvaluationSession();

  /// TaskMap::evaluate(x, cluster()) (pose in the object frame; results as documented there),
  /// answered from the cache when x is within margin() of the anchor.
  Evaluation evaluate(const Pose& x);

  /// Counters since construction or reset().
  const SessionStats& stats() const;
  /// Drops the cache (the next call searches the index) and zeroes stats().
  void reset();
  /// The margin in metres (pose distance).
  double margin() const;
  /// The cluster the session is restricted to, if any.
  std::optional<int> cluster() const;
  /// Samples currently cached (those within cutoffRadius() + margin() of the anchor).
  std::size_t cachedSamples() const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace taskmap
