#include "taskmap/integration/evaluation_session.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "kernels.hpp"
#include "nn_index.hpp"
#include "task_map_impl.hpp"
#include "taskmap/core/error.hpp"
#include "term_batch.hpp"

namespace taskmap {

using detail::IndexHit;

namespace {

/// The cache radius is (cut-off + margin) (1 + kRadiusSlack): every sample the reuse test
/// needs is inside it despite rounding of the computed distances (relative errors ~1e-15).
constexpr double kRadiusSlack = 1e-9;
/// The cached nearest is accepted if d* <= R - delta - kNearestSlack * R: uncached samples are
/// then farther than d* by far more than the rounding of any computed distance.
constexpr double kNearestSlack = 1e-9;
constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
/// Shells of the cache (by squared distance to the anchor); see State::shell_end.
constexpr std::size_t kShells = 16;

std::string num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

struct EvaluationSession::State {
  static constexpr std::size_t kStride = TaskMap::Impl::kRowStride;
  const TaskMap* map = nullptr;
  const TaskMap::Impl* impl = nullptr;
  const TaskMap::Impl::SampleSet* set = nullptr;
  std::optional<int> cluster;
  double margin = 0.0;
  double reach = 0.0;   ///< R = sqrt(cutoff2) + margin, metres
  double reach2 = 0.0;  ///< (R (1 + kRadiusSlack))^2, the anchor search's squared radius
  bool exact_tree = true;
  bool anchored = false;
  double anchor[kEmbeddingDim] = {};
  std::vector<double> rows;        ///< cached rows (embedding, weight), kStride each
  std::vector<std::size_t> grasp;  ///< grasp index of each cached row
  /// Rows of shell j (squared distance to the anchor in [j, j + 1) reach2 / kShells, the last
  /// shell also holding the rows on its outer rounding edge) end at shell_end[j].
  std::size_t shell_end[kShells] = {};
  double shells_per_reach2 = 0.0;  ///< kShells / reach2
  std::vector<IndexHit> hits;      ///< search buffer
  SessionStats stats;

  /// Searches the index around x, makes x the anchor and refills the cache. Adds the mixture
  /// terms of x to m if m is not null. Exact tree: returns the exact nearest sample (the same
  /// traversal); randomized forest: returns {kNone, inf}.
  IndexHit anchorAt(const TaskMap::Impl::Query& x, detail::MixtureSum* m);
};

IndexHit EvaluationSession::State::anchorAt(const TaskMap::Impl::Query& x, detail::MixtureSum* m) {
  ++stats.anchors;
  IndexHit nearest{kNone, std::numeric_limits<double>::infinity()};
  if (exact_tree) {
    nearest = impl->ballAndNearest(*set, x, reach2, hits);
    nearest.index = set->grasp[nearest.index];
  } else {
    impl->ballSearch(*set, x, reach2, hits);
  }
  // Cache rows in kShells shells of equal width in squared distance to the anchor, nearest
  // shell first (a counting sort): a query scans only the shells that can matter to it.
  std::size_t start[kShells + 1] = {};
  auto shellOf = [&](double d2) {
    return std::min<std::size_t>(kShells - 1, static_cast<std::size_t>(d2 * shells_per_reach2));
  };
  for (const IndexHit& h : hits) ++start[shellOf(h.distance2) + 1];
  for (std::size_t j = 0; j < kShells; ++j) start[j + 1] += start[j];
  std::copy(start + 1, start + kShells + 1, shell_end);
  rows.resize(hits.size() * kStride);
  grasp.resize(hits.size());
  for (const IndexHit& h : hits) {
    const std::size_t k = start[shellOf(h.distance2)]++;
    const double* row = set->row(h.index);
    std::copy(row, row + kStride, rows.data() + k * kStride);
    grasp[k] = set->grasp[h.index];
  }
  if (m) {
    detail::TermBatch& batch = detail::termBatch();
    batch.reserve(hits.size());
    for (const IndexHit& h : hits) {
      const double* row = set->row(h.index);
      const double w = row[kEmbeddingDim];
      if (h.distance2 > impl->cutoff2 || !(w > 0)) continue;
      double* diff = batch.nextDiff();
      for (int c = 0; c < kEmbeddingDim; ++c) diff[c] = row[c] - x.e[c];
      batch.commit(w, detail::mixtureDistance(diff, impl->inv_sp2, impl->inv_se2));
    }
    batch.flushInto(*m);
  }
  std::copy(x.e.data(), x.e.data() + kEmbeddingDim, anchor);
  anchored = true;
  return nearest;
}

EvaluationSession::EvaluationSession(const TaskMap& map, std::optional<int> cluster,
                                     std::optional<double> margin)
    : s_(std::make_unique<State>()) {
  State& s = *s_;
  s.map = &map;
  s.impl = map.impl_.get();
  s.set = &s.impl->set(cluster);  // throws for an unknown cluster
  if (s.set->size() == 0) throw Error("evaluation session: the cluster has no samples");
  s.cluster = cluster;
  s.margin = margin.value_or(kDefaultMarginFactor * map.cutoffRadius());
  if (!(std::isfinite(s.margin) && s.margin >= 0))
    throw Error(
        "evaluation session: margin = " + num(s.margin) +
        " is invalid; give a finite pose distance >= 0 in metres, or none for the default " +
        num(kDefaultMarginFactor) +
        " * cutoffRadius() = " + num(kDefaultMarginFactor * map.cutoffRadius()));
  s.reach = std::sqrt(s.impl->cutoff2) + s.margin;
  s.reach2 = s.reach * (1.0 + kRadiusSlack) * s.reach * (1.0 + kRadiusSlack);
  s.shells_per_reach2 = static_cast<double>(kShells) / s.reach2;
  s.exact_tree = s.impl->options.index == IndexKind::kExactKdTree;
  s.hits.reserve(1024);
}

EvaluationSession::EvaluationSession(EvaluationSession&&) noexcept = default;
EvaluationSession& EvaluationSession::operator=(EvaluationSession&&) noexcept = default;
EvaluationSession::~EvaluationSession() = default;

Evaluation EvaluationSession::evaluate(const Pose& x) {
  State& s = *s_;
  ++s.stats.calls;
  const TaskMap::Impl& impl = *s.impl;
  if (impl.options.quality_mode == QualityMode::kExact) return s.map->evaluate(x, s.cluster);

  const TaskMap::Impl::Query q = impl.query(x);
  const double* xe = q.e.data();
  detail::MixtureSum m;
  IndexHit nearest{kNone, std::numeric_limits<double>::infinity()};
  const double delta =
      s.anchored ? std::sqrt(detail::squaredDistance(s.anchor, xe, kEmbeddingDim)) : 0.0;
  if (!s.anchored || delta > s.margin) {
    nearest = s.anchorAt(q, &m);
    if (!s.exact_tree) {
      // The forest's contract (TaskMap::evaluate): exact nearest if the cut-off ball holds a
      // sample (the best cached one, since the ball is cached), else the forest's answer.
      const std::size_t n = s.grasp.size();
      constexpr std::size_t kStride = State::kStride;
      for (std::size_t k = 0; k < n; ++k) {
        const double d2 = detail::squaredDistance(s.rows.data() + k * kStride, xe, kEmbeddingDim);
        if (d2 <= impl.cutoff2 &&
            (d2 < nearest.distance2 || (d2 == nearest.distance2 && s.grasp[k] < nearest.index)))
          nearest = IndexHit{s.grasp[k], d2};
      }
    }
  } else {
    // Every sample within the cut-off of x is cached: the same test as the index's radius
    // search gives evaluate's term set; the best cached sample is a nearest candidate.
    // Rows are in shells by their distance rho_k to the anchor, and |x_k - x| >= rho_k - delta:
    // once a shell's inner radius exceeds delta + max(cut-off, best distance) (plus a rounding
    // slack) no row of it or beyond is a term or the nearest, and the scan stops. d2 is the index's
    // distance (squaredDistance's grouping, written out): partial sums of non-negative groups never
    // decrease, so a row whose first group already exceeds both the cut-off and the best distance
    // is skipped.
    static_assert(kEmbeddingDim == 12, "the scan below sums three groups of four");
    const double cutoff2 = impl.cutoff2;
    const double cutoff = std::sqrt(cutoff2);
    const double slack = kNearestSlack * s.reach;
    auto stopAt = [&](double best2) {
      const double r = delta + std::max(cutoff, std::sqrt(best2)) + slack;
      return r * r;
    };
    double stop2 = stopAt(std::numeric_limits<double>::infinity());
    bool any_within = false;
    constexpr std::size_t kStride = State::kStride;
    detail::TermBatch& batch = detail::termBatch();
    batch.reserve(s.grasp.size());
    std::size_t k = 0;
    for (std::size_t j = 0; j < kShells; ++j) {
      // Rows of shell j and beyond are at least sqrt(j reach2 / kShells) from the anchor.
      if (static_cast<double>(j) * (1.0 - 1e-12) > stop2 * s.shells_per_reach2) break;
      for (; k < s.shell_end[j]; ++k) {
        const double* row = s.rows.data() + k * kStride;
        double* diff = batch.nextDiff();  // x_i - x, kept if a term
        for (int c = 0; c < 4; ++c) diff[c] = row[c] - xe[c];
        double d2 = diff[0] * diff[0] + diff[1] * diff[1] + diff[2] * diff[2] + diff[3] * diff[3];
        if (d2 > cutoff2 && d2 > nearest.distance2) continue;
        for (int c = 4; c < kEmbeddingDim; ++c) diff[c] = row[c] - xe[c];
        d2 += diff[4] * diff[4] + diff[5] * diff[5] + diff[6] * diff[6] + diff[7] * diff[7];
        d2 += diff[8] * diff[8] + diff[9] * diff[9] + diff[10] * diff[10] + diff[11] * diff[11];
        if (d2 <= cutoff2) {
          const double w = row[kEmbeddingDim];
          if (w > 0) batch.commit(w, detail::mixtureDistance(diff, impl.inv_sp2, impl.inv_se2));
          any_within = true;
        }
        if (d2 < nearest.distance2 || (d2 == nearest.distance2 && s.grasp[k] < nearest.index)) {
          if (d2 < nearest.distance2) stop2 = stopAt(d2);
          nearest = IndexHit{s.grasp[k], d2};
        }
      }
    }
    batch.flushInto(m);
    if (s.exact_tree) {
      // Uncached samples are farther than R - delta from x.
      const bool certified =
          nearest.index != kNone &&
          std::sqrt(nearest.distance2) <= s.reach - delta - kNearestSlack * s.reach;
      if (!certified) {
        ++s.stats.fallbacks;
        nearest = s.anchorAt(q, nullptr);  // the mixture above is already evaluate's
      }
    } else if (!any_within) {
      nearest = IndexHit{kNone, std::numeric_limits<double>::infinity()};
    }
  }
  if (nearest.index == kNone) {  // randomized forest, empty cut-off ball
    const IndexHit h = s.set->index->nearest(xe);
    nearest = IndexHit{s.set->grasp[h.index], h.distance2};
  }
  Evaluation out;
  out.quality = impl.truncated(m, q, *s.set);
  out.proximity = impl.proximityTo(q, Neighbor{nearest.index, std::sqrt(nearest.distance2)});
  return out;
}

const SessionStats& EvaluationSession::stats() const {
  return s_->stats;
}

void EvaluationSession::reset() {
  s_->anchored = false;
  s_->rows.clear();
  s_->grasp.clear();
  std::fill(s_->shell_end, s_->shell_end + kShells, std::size_t{0});
  s_->stats = SessionStats{};
}

double EvaluationSession::margin() const {
  return s_->margin;
}

std::optional<int> EvaluationSession::cluster() const {
  return s_->cluster;
}

std::size_t EvaluationSession::cachedSamples() const {
  return s_->grasp.size();
}

}  // namespace taskmap
