#include "ball_tree.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numeric>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace taskmap {
namespace detail {
namespace {

constexpr int kDim = 7;     // (p, 2 rho q)
constexpr int kStride = 8;  // floats per point and per box corner (the 8th is 0)
/// A search of radius t in quaternion units (t^2 / (4 rho^2) = |q -+ q_i|^2) reports a sample
/// twice only if both |q - q_i|^2 and |q + q_i|^2 (which sum to 4) are within it: refusing
/// t^2 / (4 rho^2) >= kMaxQuaternionReach2 < 2 excludes that with a wide rounding margin.
constexpr double kMaxQuaternionReach2 = 1.5;
/// Coordinates at or above this magnitude are refused (float range, and error terms).
constexpr double kMaxCoordinate = 1e18;
constexpr double kFloatUnit = 0x1p-24;  // unit roundoff of float

// Sum of squares of eight lanes (a0..a3, b0..b3) in one fixed order, (a_k^2 + b_k^2) lane-wise,
// then lanes (0 + 2) + (1 + 3): the SSE and scalar paths round identically. The box and point
// distances both use it, so a box's computed distance never exceeds the computed distance of a
// point inside it (every step is monotone under rounding).
#if defined(__SSE2__)
inline float sumSquares(__m128 a, __m128 b) {
  __m128 s = _mm_add_ps(_mm_mul_ps(a, a), _mm_mul_ps(b, b));
  s = _mm_add_ps(s, _mm_movehl_ps(s, s));
  s = _mm_add_ss(s, _mm_shuffle_ps(s, s, 1));
  return _mm_cvtss_f32(s);
}
inline float pointDistance2(const float* point, __m128 y0, __m128 y1) {
  return sumSquares(_mm_sub_ps(_mm_load_ps(point), y0), _mm_sub_ps(_mm_load_ps(point + 4), y1));
}
inline float boxDistance2(const float* lo, const float* hi, __m128 y0, __m128 y1) {
  const __m128 zero = _mm_setzero_ps();
  const __m128 a = _mm_max_ps(
      _mm_max_ps(_mm_sub_ps(_mm_load_ps(lo), y0), _mm_sub_ps(y0, _mm_load_ps(hi))), zero);
  const __m128 b = _mm_max_ps(
      _mm_max_ps(_mm_sub_ps(_mm_load_ps(lo + 4), y1), _mm_sub_ps(y1, _mm_load_ps(hi + 4))), zero);
  return sumSquares(a, b);
}
#else
inline float sumSquares(const float* d) {
  float s[4];
  for (int k = 0; k < 4; ++k) s[k] = d[k] * d[k] + d[k + 4] * d[k + 4];
  return (s[0] + s[2]) + (s[1] + s[3]);
}
#endif

/// The squared distances from one 7-D query y (8 floats, the 8th 0) to a point (8 floats) and
/// to a box [lo, hi] (8 floats each; 0 inside); all 16-byte aligned.
#if defined(__SSE2__)
class Distances {
 public:
  explicit Distances(const float* y) : y0_(_mm_load_ps(y)), y1_(_mm_load_ps(y + 4)) {}
  float point(const float* p) const { return pointDistance2(p, y0_, y1_); }
  float box(const float* lo, const float* hi) const { return boxDistance2(lo, hi, y0_, y1_); }

 private:
  __m128 y0_, y1_;
};
#else
class Distances {
 public:
  explicit Distances(const float* y) : y_(y) {}
  float point(const float* p) const {
    float d[kStride];
    for (int k = 0; k < kStride; ++k) d[k] = p[k] - y_[k];
    return sumSquares(d);
  }
  float box(const float* lo, const float* hi) const {
    float d[kStride];
    for (int k = 0; k < kStride; ++k) d[k] = std::max(std::max(lo[k] - y_[k], y_[k] - hi[k]), 0.0f);
    return sumSquares(d);
  }

 private:
  const float* y_;
};
#endif

}  // namespace

std::unique_ptr<PoseBallTree> PoseBallTree::build(
    const std::vector<Eigen::Vector3d>& positions,
    const std::vector<Eigen::Vector4d>& quaternions_wxyz, double rho) {
  assert(positions.size() == quaternions_wxyz.size());
  const std::size_t n = positions.size();
  if (n == 0 || n > std::numeric_limits<std::int32_t>::max() || !(rho > 0)) return nullptr;
  std::unique_ptr<PoseBallTree> tree(new PoseBallTree());
  tree->rho_ = rho;
  std::vector<float> coords(n * kStride, 0.0f);
  double max_abs = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector4d q = quaternions_wxyz[i];
    if (q[0] < 0) q = -q;  // w >= 0
    double y[kDim] = {positions[i].x(), positions[i].y(), positions[i].z(), 2 * rho * q[0],
                      2 * rho * q[1],   2 * rho * q[2],   2 * rho * q[3]};
    for (int k = 0; k < kDim; ++k) {
      if (!(std::abs(y[k]) < kMaxCoordinate)) return nullptr;
      coords[i * kStride + k] = static_cast<float>(y[k]);
      max_abs = std::max(max_abs, std::abs(static_cast<double>(coords[i * kStride + k])));
    }
  }
  tree->max_abs_ = static_cast<float>(max_abs);
  std::vector<std::uint32_t> index(n);
  std::iota(index.begin(), index.end(), 0u);
  tree->buildRange(coords, index, 0, static_cast<std::uint32_t>(n));
  tree->points_.resize(n * kStride);
  for (std::size_t k = 0; k < n; ++k)
    std::copy(coords.begin() + std::size_t{index[k]} * kStride,
              coords.begin() + (std::size_t{index[k]} + 1) * kStride,
              tree->points_.begin() + static_cast<std::ptrdiff_t>(k * kStride));
  tree->order_ = std::move(index);
  return tree;
}

// Splits [begin, end) of index at the median of the widest coordinate of its bounding box
// until at most kLeafSize points remain. Returns the child code (node index, or ~leaf).
int PoseBallTree::buildRange(std::vector<float>& coords, std::vector<std::uint32_t>& index,
                             std::uint32_t begin, std::uint32_t end) {
  auto box = [&](std::uint32_t b, std::uint32_t e, float* lo, float* hi) {
    std::fill(lo, lo + kStride, std::numeric_limits<float>::max());
    std::fill(hi, hi + kStride, std::numeric_limits<float>::lowest());
    for (std::uint32_t i = b; i < e; ++i)
      for (int k = 0; k < kStride; ++k) {
        lo[k] = std::min(lo[k], coords[std::size_t{index[i]} * kStride + k]);
        hi[k] = std::max(hi[k], coords[std::size_t{index[i]} * kStride + k]);
      }
  };
  if (end - begin <= static_cast<std::uint32_t>(kLeafSize)) {
    leaves_.push_back(Leaf{begin, end});
    return ~static_cast<int>(leaves_.size() - 1);
  }
  float lo[kStride], hi[kStride];
  box(begin, end, lo, hi);
  int split = 0;
  for (int k = 1; k < kDim; ++k)
    if (hi[k] - lo[k] > hi[split] - lo[split]) split = k;
  const std::uint32_t mid = begin + (end - begin) / 2;
  // Ties by sample index: the partition depends on the samples only.
  std::nth_element(index.begin() + begin, index.begin() + mid, index.begin() + end,
                   [&](std::uint32_t a, std::uint32_t b) {
                     const float va = coords[std::size_t{a} * kStride + split],
                                 vb = coords[std::size_t{b} * kStride + split];
                     return va < vb || (va == vb && a < b);
                   });
  const int me = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Node node{};
  box(begin, mid, node.lo[0], node.hi[0]);
  box(mid, end, node.lo[1], node.hi[1]);
  node.child[0] = buildRange(coords, index, begin, mid);
  node.child[1] = buildRange(coords, index, mid, end);
  nodes_[static_cast<std::size_t>(me)] = node;
  return me;
}

float PoseBallTree::floatRadius2(double r, const float* y) const {
  // x*(r) = 2 - sqrt(4 - a), a = r^2 / rho^2, written without cancellation.
  const double a = r * r / (rho_ * rho_);
  const double xs = a >= 4.0 ? 2.0 : a / (2.0 + std::sqrt(4.0 - a));
  const double ry = std::sqrt(r * r + rho_ * rho_ * xs * xs);
  // Each float coordinate difference is within 5 u M of the exact one (rounding of the sample,
  // of the query and of the subtraction; M bounds every |coordinate|), so the float distance
  // vector is within 5 sqrt7 u M of the exact one; the float sum of squares adds 4 roundings
  // (relative 4u), covered by the factor 1 + 1e-6.
  double m = max_abs_;
  for (int k = 0; k < kDim; ++k) m = std::max(m, static_cast<double>(std::abs(y[k])));
  const double rf = ry + 5.0 * std::sqrt(7.0) * kFloatUnit * m;
  const double rf2 = rf * rf * (1.0 + 1e-6);
  if (!(rf2 < std::numeric_limits<float>::max())) return std::numeric_limits<float>::infinity();
  return std::nextafter(static_cast<float>(rf2), std::numeric_limits<float>::infinity());
}

namespace {

/// The 7-D query point y = (p, 2 rho u, 0) in float (8 floats), u = q normalised with w >= 0,
/// and u's w in *w; false if a coordinate is not finite (the tree cannot answer).
bool queryPoint(const Eigen::Vector3d& p, const Eigen::Quaterniond& q, double rho, float* y,
                double* w) {
  Eigen::Vector4d u(q.w(), q.x(), q.y(), q.z());
  u.normalize();
  if (u[0] < 0) u = -u;
  y[0] = static_cast<float>(p.x());
  y[1] = static_cast<float>(p.y());
  y[2] = static_cast<float>(p.z());
  for (int k = 0; k < 4; ++k) y[3 + k] = static_cast<float>(2 * rho * u[k]);
  y[7] = 0.0f;
  for (int k = 0; k < kDim; ++k)
    if (!std::isfinite(y[k])) return false;
  *w = u[0];
  return true;
}

}  // namespace

bool PoseBallTree::candidates(const Eigen::Vector3d& p, const Eigen::Quaterniond& q, double r,
                              std::vector<std::uint32_t>& out, const void* rows,
                              std::size_t row_bytes) const {
  out.clear();
  if (!(std::isfinite(r) && r >= 0)) return false;
  alignas(16) float y[kStride];
  double w = 0.0;
  if (!queryPoint(p, q, rho_, y, &w)) return false;
  const float radius2 = floatRadius2(r, y);
  // Not in the domain (a sample could be found twice).
  if (!(radius2 / (4.0 * rho_ * rho_) < kMaxQuaternionReach2)) return false;
  search(y, radius2, out, static_cast<const char*>(rows), row_bytes);
  // Samples nearer to -q need a search around -q only if w <= sqrt(x*(r)) <= t / (2 rho).
  const double reach = std::sqrt(static_cast<double>(radius2)) / (2.0 * rho_);
  if (w <= reach) {
    for (int k = 3; k < kDim; ++k) y[k] = -y[k];
    search(y, radius2, out, static_cast<const char*>(rows), row_bytes);
  }
  return true;
}

bool PoseBallTree::nearest(const Eigen::Vector3d& p, const Eigen::Quaterniond& q,
                           ExactDistance exact, const std::size_t* keys, std::uint32_t& best,
                           double& best_distance2) const {
  alignas(16) float y[kStride];
  double w = 0.0;
  if (!queryPoint(p, q, rho_, y, &w)) return false;
  bool found = false;
  std::uint32_t best_k = 0;
  double best_d2 = std::numeric_limits<double>::infinity();
  float bound2 = std::numeric_limits<float>::infinity();  // 7-D pruning radius^2 for best_d2
  // One branch and bound around q, then around -q if a sample nearer to -q can still beat the
  // best: it has w_i <= sqrt(x*) and the query w <= sqrt(x*) with x* = x*(best distance).
  for (int sign = 0; sign < 2; ++sign) {
    if (sign == 1) {
      const double reach = std::sqrt(static_cast<double>(bound2)) / (2.0 * rho_);
      if (!(w <= reach)) break;
      for (int k = 3; k < kDim; ++k) y[k] = -y[k];
    }
    const Distances dist(y);
    auto point2 = [&](std::uint32_t i) { return dist.point(&points_[std::size_t{i} * kStride]); };
    auto box2 = [&](const float* lo, const float* hi) { return dist.box(lo, hi); };
    struct Entry {
      int child;
      float distance2;
    };
    Entry stack[80];
    int top = 0;
    stack[top++] = Entry{nodes_.empty() ? ~0 : 0, 0.0f};
    while (top > 0) {
      const Entry e = stack[--top];
      if (e.distance2 > bound2) continue;
      if (e.child < 0) {
        const Leaf& leaf = leaves_[static_cast<std::size_t>(~e.child)];
        for (std::uint32_t i = leaf.begin; i < leaf.end; ++i) {
          if (point2(i) > bound2) continue;
          const double d2 = exact.distance2(exact.context, i);
          if (found && (d2 > best_d2 || (d2 == best_d2 && keys[i] >= keys[best_k]))) continue;
          found = true;
          best_k = i;
          if (d2 < best_d2) {
            best_d2 = d2;
            bound2 = floatRadius2(std::sqrt(d2), y);
          }
        }
        continue;
      }
      const Node& node = nodes_[static_cast<std::size_t>(e.child)];
      const float d0 = box2(node.lo[0], node.hi[0]), d1 = box2(node.lo[1], node.hi[1]);
      // The nearer child on top of the stack: it is searched first and tightens the bound.
      const int nearer = d0 <= d1 ? 0 : 1;
      stack[top++] = Entry{node.child[1 - nearer], nearer == 0 ? d1 : d0};
      stack[top++] = Entry{node.child[nearer], nearer == 0 ? d0 : d1};
      assert(top <= 78);
    }
  }
  if (!found) return false;
  best = best_k;
  best_distance2 = best_d2;
  return true;
}

void PoseBallTree::search(const float* y, float radius2, std::vector<std::uint32_t>& out,
                          const char* rows, std::size_t row_bytes) const {
  std::size_t count = out.size();
  // Branch-free leaf scans write every point and advance by the test: keep room for a leaf.
  auto reserveLeaf = [&] {
    if (out.size() < count + kLeafSize) out.resize(std::max(2 * out.size(), count + kLeafSize));
  };
  const Distances dist(y);
  auto point2 = [&](std::uint32_t i) { return dist.point(&points_[std::size_t{i} * kStride]); };
  auto box2 = [&](const float* lo, const float* hi) { return dist.box(lo, hi); };
  // Two passes: the hierarchy first, collecting the leaves that meet the ball and prefetching
  // their points, then the leaf scans, so that the memory system fetches every leaf at once
  // instead of one after another. The depth of a median split tree is < 32 (n < 2^31) and each
  // level pushes at most two children.
  int stack[80];
  int top = 0;
  auto scanLeaf = [&](int l) {
    const Leaf& leaf = leaves_[static_cast<std::size_t>(l)];
    reserveLeaf();
    std::uint32_t* dst = out.data();
#if defined(__SSE2__)
    const std::size_t first = count;
#endif
    for (std::uint32_t i = leaf.begin; i < leaf.end; ++i) {
      dst[count] = i;
      count += point2(i) <= radius2 ? 1 : 0;
    }
#if defined(__SSE2__)
    if (rows)
      for (std::size_t k = first; k < count; ++k) {
        const char* row = rows + dst[k] * row_bytes;
        for (std::size_t b = 0; b < row_bytes; b += 64) _mm_prefetch(row + b, _MM_HINT_T0);
        _mm_prefetch(row + row_bytes - 1, _MM_HINT_T0);
      }
#else
    (void)rows;  // prefetching needs SSE
    (void)row_bytes;
#endif
  };
  // The leaves met, scanned after the traversal; beyond kMaxLeaves of them (radii far above
  // the cut-off) the others are scanned as they are met.
  constexpr int kMaxLeaves = 256;
  int hit_leaves[kMaxLeaves];
  int leaves_found = 0;
  stack[top++] = nodes_.empty() ? ~0 : 0;
  while (top > 0) {
    const int c = stack[--top];
    if (c < 0) {
      if (leaves_found == kMaxLeaves) {
        scanLeaf(~c);
        continue;
      }
      hit_leaves[leaves_found++] = ~c;
#if defined(__SSE2__)
      const Leaf& leaf = leaves_[static_cast<std::size_t>(~c)];
      const char* b = reinterpret_cast<const char*>(&points_[std::size_t{leaf.begin} * kStride]);
      const char* e = reinterpret_cast<const char*>(&points_[std::size_t{leaf.end} * kStride]);
      for (; b < e; b += 64) _mm_prefetch(b, _MM_HINT_T0);
#endif
      continue;
    }
    const Node& node = nodes_[static_cast<std::size_t>(c)];
    // Second child pushed first: the first child's subtree is searched first.
    if (box2(node.lo[1], node.hi[1]) <= radius2) stack[top++] = node.child[1];
    if (box2(node.lo[0], node.hi[0]) <= radius2) stack[top++] = node.child[0];
    assert(top <= 78);
  }
  for (int j = 0; j < leaves_found; ++j) scanLeaf(hit_leaves[j]);
  out.resize(count);
}

}  // namespace detail
}  // namespace taskmap
