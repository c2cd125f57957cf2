#pragma once
// Private: candidate search for pose-distance balls, the radius search behind the truncated
// quality (TaskMap::evaluate and quality, EvaluationSession refills). FLANN stays the index of
// nearest / knn / radius; this hierarchy answers only "which samples may lie within r of x".
//
// Why a second structure: the pose distance is Euclidean in the 12-D embedding
// x = (p, rho/sqrt2 vec R), but a kd-tree over those 12 doubles splits a 6-D set along 9
// rotation-matrix axes and reads 96 bytes per point; FLANN's and nanoflann's exact searches
// there cost 9-17 us at the cut-off on a 1e5-sample map (tests/bench/integration). The same
// ball is nearly a Euclidean ball in 7 coordinates y = (p, 2 rho q) (below), which a bounding-
// box hierarchy over floats with branch-free leaf scans searches in about 1.5 us.
//
// The bound. With x_q = min(|q - q_i|^2, |q + q_i|^2) in [0, 2] (unit quaternions),
// ||R - R_i||_F^2 = 8 sin^2(theta/2) = 8 x_q - 2 x_q^2, so the pose distance is
//   D^2 = |dp|^2 + (rho^2/2) ||R - R_i||_F^2 = |dp|^2 + 4 rho^2 x_q - rho^2 x_q^2,
// and the 7-D distance to the closer sign is t^2 = |dp|^2 + 4 rho^2 x_q = D^2 + rho^2 x_q^2.
// D <= r implies 4 x_q - x_q^2 <= r^2/rho^2, i.e. x_q <= x*(r) = 2 - sqrt(4 - r^2/rho^2)
// (2 if r >= 2 rho), hence t^2 <= r^2 + rho^2 x*(r)^2: every sample of the pose ball lies in
// the 7-D ball of that radius (at the default cut-off x* is about 0.01, the 7-D ball 0.1%
// wider). Samples are stored with w >= 0 and searched around the query's q with w >= 0; a
// sample nearer to -q has w_i <= sqrt(x_q) (|q + q_i|^2 >= (w + w_i)^2), so a second search
// around -q is needed only when the query's w <= sqrt(x*(r)).

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "huge_page_allocator.hpp"

namespace taskmap {
namespace detail {

/// Bounding-box hierarchy over the samples' (p, 2 rho q) in float. Read-only after build();
/// candidates() is const and thread-safe.
class PoseBallTree {
 public:
  /// Points per leaf, chosen by measurement (tests/bench/integration).
  static constexpr int kLeafSize = 32;

  /// Builds over n samples: positions[i] (metres) and unit quaternions[i] (w x y z order as
  /// Eigen stores coeffs x y z w; any sign). rho: metres per radian of the pose distance.
  /// Returns null when float coordinates cannot represent the samples (|coordinate| >= 1e18).
  static std::unique_ptr<PoseBallTree> build(const std::vector<Eigen::Vector3d>& positions,
                                             const std::vector<Eigen::Vector4d>& quaternions_wxyz,
                                             double rho);

  /// Samples in the hierarchy's leaf order: rows stored in this order make a search's
  /// candidates contiguous blocks. candidates() reports positions in this order.
  const std::vector<std::uint32_t>& order() const { return order_; }

  /// Every sample within pose distance r of (p, q) (q unit, any sign), and a few more: the
  /// caller filters by the exact distance. Writes positions in order() (each at most once,
  /// unsorted) to out (cleared first) and returns true; returns false (out empty) when it
  /// cannot answer: r not finite, or so large against rho that both signs of a quaternion
  /// lie in the 7-D ball (a sample could come twice), or a non-finite query. The caller then
  /// uses the index.
  /// If rows is not null, the caller's per-sample data (row k at rows + k * row_bytes, k a
  /// position in order()) of each candidate is prefetched as the search goes on.
  bool candidates(const Eigen::Vector3d& p, const Eigen::Quaterniond& q, double r,
                  std::vector<std::uint32_t>& out, const void* rows = nullptr,
                  std::size_t row_bytes = 0) const;

  /// The caller's exact squared pose distance of the sample at position k of order().
  struct ExactDistance {
    const void* context;
    double (*distance2)(const void* context, std::uint32_t k);
  };
  /// The nearest sample to (p, q) by exact.distance2 (which must be the pose distance D^2 up to
  /// rounding of ~1e-15 relative), ties to the smaller keys[k]: a branch and bound whose 7-D
  /// pruning radius follows the best distance found (the bound above with r = best D, inflated
  /// like the candidates' radius). Writes the position in order() and its exact distance;
  /// returns false (nothing written) for a non-finite query.
  bool nearest(const Eigen::Vector3d& p, const Eigen::Quaterniond& q, ExactDistance exact,
               const std::size_t* keys, std::uint32_t& best, double& best_distance2) const;

  std::size_t size() const { return order_.size(); }

 private:
  /// Inner node: the bounding boxes of its two children (8 floats each, the 8th is 0) and the
  /// children, >= 0 an inner node, < 0 the leaf ~child.
  struct alignas(16) Node {
    float lo[2][8];
    float hi[2][8];
    std::int32_t child[2];
  };
  struct Leaf {
    std::uint32_t begin, end;
  };
  PoseBallTree() = default;
  int buildRange(std::vector<float>& coords, std::vector<std::uint32_t>& index, std::uint32_t begin,
                 std::uint32_t end);
  /// The squared 7-D search radius in float for pose radius r around query y (7 floats),
  /// inflated to cover every rounding of the float coordinates and arithmetic.
  float floatRadius2(double r, const float* y) const;
  void search(const float* y, float radius2, std::vector<std::uint32_t>& out, const char* rows,
              std::size_t row_bytes) const;

  double rho_ = 0.0;
  float max_abs_ = 0.0f;      ///< largest |coordinate| of the samples
  HugeVector<Node> nodes_;    ///< inner nodes, root first (none if one leaf)
  std::vector<Leaf> leaves_;  ///< ranges of points_
  HugeVector<float> points_;  ///< 8 floats per sample (y, 0), in order()
  std::vector<std::uint32_t> order_;
};

}  // namespace detail
}  // namespace taskmap
