// The cut-off searches of the truncated quality: candidates from the ball tree, filtered by
// the index's exact distance (the same set as NnIndex::radius), else the index itself.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "kernels.hpp"
#include "nn_index.hpp"
#include "task_map_impl.hpp"
#include "term_batch.hpp"

namespace taskmap {

using detail::IndexHit;

namespace {

/// Candidates of the calling thread's last search (a query allocates nothing once grown).
std::vector<std::uint32_t>& candidateBuffer() {
  thread_local std::vector<std::uint32_t> buffer;
  return buffer;
}

}  // namespace

bool TaskMap::Impl::ballCandidates(const SampleSet& s, const Query& x, double radius2,
                                   std::vector<std::uint32_t>& out) {
  return s.ball && s.ball->candidates(x.p, x.q, std::sqrt(radius2), out, s.rows.data(),
                                      kRowStride * sizeof(double));
}

void TaskMap::Impl::ballSearch(const SampleSet& s, const Query& x, double radius2,
                               std::vector<IndexHit>& out) const {
  auto& candidates = candidateBuffer();
  if (!ballCandidates(s, x, radius2, candidates)) {
    s.index->radius(x.e.data(), radius2, out);
    return;
  }
  out.clear();
  for (const std::uint32_t k : candidates) {
    // The index's arithmetic: the same set, and the same distances, as NnIndex::radius.
    const double d2 = detail::squaredDistance(s.row(k), x.e.data(), kEmbeddingDim);
    if (d2 <= radius2) out.push_back(IndexHit{k, d2});
  }
}

IndexHit TaskMap::Impl::nearestOutsideBall(const SampleSet& s, const Query& x) const {
  if (s.ball && options.index == IndexKind::kExactKdTree) {
    struct Context {
      const SampleSet* s;
      const double* x;
    } context{&s, x.e.data()};
    const detail::PoseBallTree::ExactDistance exact{
        &context, [](const void* c, std::uint32_t k) {
          const auto* ctx = static_cast<const Context*>(c);
          return detail::squaredDistance(ctx->s->row(k), ctx->x, kEmbeddingDim);
        }};
    IndexHit h{0, 0.0};
    std::uint32_t k = 0;
    if (s.ball->nearest(x.p, x.q, exact, s.grasp.data(), k, h.distance2)) {
      h.index = k;
      return h;
    }
  }
  return s.index->nearest(x.e.data());
}

IndexHit TaskMap::Impl::ballAndNearest(const SampleSet& s, const Query& x, double radius2,
                                       std::vector<IndexHit>& out) const {
  if (!s.ball) return s.index->radiusAndNearest(x.e.data(), radius2, out);
  ballSearch(s, x, radius2, out);
  if (out.empty()) return nearestOutsideBall(s, x);
  return *std::min_element(out.begin(), out.end(),
                           [&](const IndexHit& a, const IndexHit& b) { return nearer(s, a, b); });
}

IndexHit TaskMap::Impl::cutoffMixture(const SampleSet& s, const Query& x,
                                      detail::MixtureSum& m) const {
  const double* xe = x.e.data();
  auto& candidates = candidateBuffer();
  if (!ballCandidates(s, x, cutoff2, candidates)) {
    thread_local std::vector<IndexHit> hits;
    const IndexHit nearest = s.index->radiusAndNearest(xe, cutoff2, hits);
    for (const IndexHit& h : hits) detail::addMixtureTerm(s.row(h.index), xe, inv_sp2, inv_se2, m);
    return nearest;
  }
  // First pass over the candidates: the exact distance (the index's); for the samples within
  // the cut-off the nearest so far, and for the terms (weight > 0) the differences and the
  // kernel's exponent. Then the exps of all terms at once (expBatch), then the sums.
  detail::TermBatch& batch = detail::termBatch();
  batch.reserve(candidates.size());
  IndexHit best{0, std::numeric_limits<double>::infinity()};
  bool found = false;
  for (const std::uint32_t k : candidates) {
    const double* row = s.row(k);
    double* diff = batch.nextDiff();  // x_i - x, kept if a term
    double sq[kEmbeddingDim];         // diff^2
#if defined(__SSE2__)
    for (int c = 0; c < kEmbeddingDim; c += 2) {
      const __m128d d = _mm_sub_pd(_mm_loadu_pd(row + c), _mm_loadu_pd(xe + c));
      _mm_storeu_pd(diff + c, d);
      _mm_storeu_pd(sq + c, _mm_mul_pd(d, d));
    }
#else
    for (int c = 0; c < kEmbeddingDim; ++c) {
      diff[c] = row[c] - xe[c];
      sq[c] = diff[c] * diff[c];
    }
#endif
    // The index's distance (squaredDistance's order) and the kernel's (mixtureDistance's)
    // from the same squares.
    const double d2 = ((sq[0] + sq[1]) + sq[2] + sq[3]) + (sq[4] + sq[5] + sq[6] + sq[7]) +
                      (sq[8] + sq[9] + sq[10] + sq[11]);
    if (d2 > cutoff2) continue;
    const IndexHit h{k, d2};
    if (!found || nearer(s, h, best)) best = h;
    found = true;
    const double w = row[kWeightColumn];
    if (w > 0) {
      const double dp2 = sq[0] + sq[1] + sq[2];
      const double dr2 = sq[3] + sq[4] + sq[5] + sq[6] + sq[7] + sq[8] + sq[9] + sq[10] + sq[11];
      batch.commit(w, dp2 * inv_sp2 + dr2 * inv_se2);
    }
  }
  batch.flushInto(m);
  return found ? best : nearestOutsideBall(s, x);
}

}  // namespace taskmap
