// Baselines of integration_bench (baselines.hpp): nanoflann and brute force.
#include "baselines.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include <nanoflann.hpp>

#include "taskmap/integration/criteria.hpp"

namespace taskmap {
namespace bench {
namespace {

/// nanoflann dataset adaptor over row-major points of Dim coordinates of type T.
template <typename T, int Dim>
struct Cloud {
  std::vector<T> v;
  std::size_t kdtree_get_point_count() const { return v.size() / Dim; }
  T kdtree_get_pt(std::size_t i, std::size_t d) const { return v[i * Dim + d]; }
  template <class B>
  bool kdtree_get_bbox(B&) const {
    return false;
  }
};
using Cloud12 = Cloud<double, kEmbeddingDim>;  // the embedding
using NanoTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Cloud12>,
                                                     Cloud12, kEmbeddingDim, std::size_t>;

// The 7-D float points y = (p, 2 rho q), q = (w, x, y, z) with w >= 0, as TaskMap's ball tree.
constexpr int kBallDim = 7;
using Cloud7 = Cloud<float, kBallDim>;
using NanoTree7 =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud7, float>, Cloud7,
                                        kBallDim, std::uint32_t>;
// Leaf size of the 7-D tree: 32, the fastest of 10, 16, 32. Evaluate p50 in us, medians of 9
// interleaved runs, mixed / near set (the radius search alone in brackets): 10: 33.9 / 28.2
// (5.7 / 9.5); 16: 30.5 / 26.8 (5.8 / 8.6); 32: 33.0 / 25.4 (4.8 / 7.8). The mixed p50 also
// includes the 12-D nearest of the ~35% of mixed queries with no sample within the cut-off.
constexpr std::size_t kLeaf7 = 32;

}  // namespace

struct Baselines::Impl {
  const TaskMap& map;
  std::vector<Pose> queries;
  std::vector<PoseEmbedding, Eigen::aligned_allocator<PoseEmbedding>> query_embedding;
  Cloud12 cloud;
  std::unique_ptr<NanoTree> nano;
  Cloud7 cloud7;
  std::unique_ptr<NanoTree7> nano7;
  std::vector<std::array<float, kBallDim>> query7;  // queries' (p, 2 rho q), w >= 0
  std::vector<bool> query7_flip;      // search around -q too: w <= sqrt(x*(r_c)) (1 + 1e-5)
  float radius7_2 = 0;                // squared 7-D radius at the cut-off (radius + 1e-5 relative)
  std::vector<double> rows7;          // 12-D rows in the 7-D tree's leaf order
  std::vector<std::uint32_t> grasp7;  // grasp index of each of them
  std::vector<Eigen::Vector3d> pos;
  std::vector<Eigen::Quaterniond, Eigen::aligned_allocator<Eigen::Quaterniond>> qconj;
  std::vector<double> w;
  double wsum = 0, isp2 = 0, ise2 = 0, sr = 0, rho = 0, inv_z = 0, wp = 0, wr = 0;

  Impl(const TaskMap& m, const std::vector<Pose>& qs) : map(m), queries(qs) {
    const double sp = *map.options().position_sigma;
    sr = *map.options().rotation_sigma;
    rho = map.rotationScale();
    for (const Pose& x : queries) query_embedding.push_back(embedPose(x, rho));
    // x*(r_c) = 2 - sqrt(4 - a), a = r_c^2 / rho^2 (2 if a >= 4); 7-D radius^2 r_c^2 + rho^2 x*^2.
    const double rc = map.cutoffRadius(), a = rc * rc / (rho * rho);
    const double xs = a >= 4 ? 2.0 : a / (2 + std::sqrt(4 - a));
    // Radius slack 1e-5 relative: float rounding of coordinates up to 0.4 m moves 7-D distances
    // by at most about sqrt7 * 2 * 2^-24 * 0.4 m = 1.3e-7 m, 7e-6 of the radius.
    const double r7 = std::sqrt(rc * rc + rho * rho * xs * xs) * (1 + 1e-5);
    radius7_2 = static_cast<float>(r7 * r7);
    for (const Pose& x : queries) {
      const auto y = point7(x.position, x.orientation);
      query7.push_back(y);
      query7_flip.push_back(y[3] <= 2 * rho * std::sqrt(xs) * 1.00001);
    }
    for (std::size_t i = 0; i < map.size(); ++i) {
      const Pose p = map.pose(i);
      const PoseEmbedding e = embedPose(p, rho);
      cloud.v.insert(cloud.v.end(), e.data(), e.data() + kEmbeddingDim);
      const auto y = point7(p.position, p.orientation);
      cloud7.v.insert(cloud7.v.end(), y.begin(), y.end());
      pos.push_back(p.position);
      qconj.push_back(p.orientation.conjugate());
      w.push_back(map.data().grasps.epsilon[i]);
      wsum += w.back();
    }
    nano = std::make_unique<NanoTree>(kEmbeddingDim, cloud,
                                      nanoflann::KDTreeSingleIndexAdaptorParams(10));
    nano->buildIndex();
    {
      // The 7-D points, and a copy of their 12-D rows, in the tree's leaf order (as TaskMap
      // keeps its rows): a leaf's candidates are then contiguous in both. The tree over the
      // reordered points has the same leaves (splits depend on the point set only).
      NanoTree7 first(kBallDim, cloud7, nanoflann::KDTreeSingleIndexAdaptorParams(kLeaf7));
      first.buildIndex();
      Cloud7 ordered;
      for (const std::uint32_t i : first.vAcc) {
        ordered.v.insert(ordered.v.end(), cloud7.v.begin() + i * kBallDim,
                         cloud7.v.begin() + (i + 1) * kBallDim);
        rows7.insert(rows7.end(), cloud.v.begin() + i * kEmbeddingDim,
                     cloud.v.begin() + (i + 1) * kEmbeddingDim);
        grasp7.push_back(i);
      }
      cloud7 = std::move(ordered);
    }
    nano7 = std::make_unique<NanoTree7>(kBallDim, cloud7,
                                        nanoflann::KDTreeSingleIndexAdaptorParams(kLeaf7));
    nano7->buildIndex();
    isp2 = 1 / (sp * sp);
    ise2 = 1 / (rho * sr * rho * sr);
    inv_z = 1 / gaussianNormaliser(sp, sr);
    wp = map.options().linear_weight;
    wr = *map.options().angular_weight;
  }

  std::array<float, kBallDim> point7(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) const {
    Eigen::Vector4d u(q.w(), q.x(), q.y(), q.z());
    u.normalize();
    if (u[0] < 0) u = -u;
    std::array<float, kBallDim> y;
    for (int k = 0; k < 3; ++k) y[k] = static_cast<float>(p[k]);
    for (int k = 0; k < 4; ++k) y[3 + k] = static_cast<float>(2 * rho * u[k]);
    return y;
  }

  static Eigen::Vector3d relLog(const Eigen::Quaterniond& qc, const Eigen::Quaterniond& q) {
    Eigen::Quaterniond r = qc * q;
    double s = r.vec().norm(), c = r.w();
    Eigen::Vector3d v = r.vec();
    if (c < 0) {
      c = -c;
      v = -v;
    }
    return s < 1e-9 ? Eigen::Vector3d((2.0 / c) * v)
                    : Eigen::Vector3d((2.0 * std::atan2(s, c) / s) * v);
  }

  // Running sums of the mixture: sum c_i and sum c_i (x_i - x) in the embedding.
  struct Mixture {
    double sum = 0;
    Eigen::Matrix<double, kEmbeddingDim, 1> moment =
        Eigen::Matrix<double, kEmbeddingDim, 1>::Zero();
  };
  // Adds sample i, c_i = w_i exp(-d_i/2), d_i = |dp|^2/sp^2 + ||R_i - R||_F^2 / (2 sr^2)
  // = |dx_p|^2/sp^2 + |dx_R|^2/(rho sr)^2 in the embedding, if |dx|^2 <= max_d2. Returns |dx|^2
  // (index distance).
  double addTerm(std::size_t qi, std::size_t i, Mixture& m,
                 double max_d2 = std::numeric_limits<double>::infinity(),
                 const double* row = nullptr) const {
    if (!row) row = cloud.v.data() + i * kEmbeddingDim;
    const Eigen::Matrix<double, kEmbeddingDim, 1> diff =
        Eigen::Map<const Eigen::Matrix<double, kEmbeddingDim, 1>>(row) - query_embedding[qi];
    const double dp2 = diff.head<3>().squaredNorm(), dr2 = diff.tail<9>().squaredNorm();
    const double d = dp2 * isp2 + dr2 * ise2;
    if (w[i] > 0 && d < 1492 && dp2 + dr2 <= max_d2) {  // exp(-746) is 0 in double precision
      const double c = w[i] * std::exp(-0.5 * d);
      m.sum += c;
      m.moment += c * diff;
    }
    return dp2 + dr2;
  }

  // The same criteria as TaskMap::evaluate, given the nearest sample and the mixture sums:
  // dg_q/dp = -(scale/sp^2) sum c_i (p_i - p); dg_q/dw = (scale/(2 sr^2)) v(R S^T) with
  // S = sum c_i (R_i - R), v(A) = (A21 - A12, A02 - A20, A10 - A01) (criteria.hpp).
  Evaluation finish(std::size_t qi, std::size_t nearest, double nearest_d2,
                    const Mixture& m) const {
    const Pose& x = queries[qi];
    const Eigen::Quaterniond q = x.orientation.normalized();
    const Eigen::Matrix3d r = q.toRotationMatrix();
    const double scale = inv_z / wsum;
    Evaluation out;
    out.quality.value = -m.sum * scale;
    const Eigen::Matrix3d s =
        Eigen::Map<const Eigen::Matrix3d>(m.moment.data() + 3) * (std::sqrt(2.0) / rho);
    const Eigen::Matrix3d a = r * s.transpose();
    out.quality.gradient << -scale * isp2 * m.moment.head<3>(),
        (0.5 * scale / (sr * sr)) *
            Eigen::Vector3d(a(2, 1) - a(1, 2), a(0, 2) - a(2, 0), a(1, 0) - a(0, 1));
    const Eigen::Vector3d dp = x.position - pos[nearest];
    const Eigen::Vector3d om = relLog(qconj[nearest], q);
    out.proximity.nearest = Neighbor{nearest, std::sqrt(nearest_d2)};
    out.proximity.value = wp * dp.squaredNorm() + wr * om.squaredNorm();
    out.proximity.gradient << 2 * wp * dp, 2 * wr * (r * om);
    return out;
  }

  Evaluation nanoEvaluate(std::size_t qi) const {
    thread_local std::vector<std::pair<std::size_t, double>> hits;
    hits.clear();
    const double r2 = map.cutoffRadius() * map.cutoffRadius();
    nano->radiusSearch(query_embedding[qi].data(), r2, hits, nanoflann::SearchParams(32, 0, false));
    std::size_t best = 0;
    double best_d2 = std::numeric_limits<double>::max();
    Mixture m;
    for (const auto& h : hits) {
      addTerm(qi, h.first, m);
      if (h.second < best_d2) {
        best_d2 = h.second;
        best = h.first;
      }
    }
    if (hits.empty()) {
      nanoflann::KNNResultSet<double, std::size_t> rs(1);
      rs.init(&best, &best_d2);
      nano->findNeighbors(rs, query_embedding[qi].data(), nanoflann::SearchParams());
    }
    return finish(qi, best, best_d2, m);
  }

  // TaskMap's search with nanoflann: the 7-D ball around (p, 2 rho q), and around -q if w <=
  // sqrt(x*), filtered by the exact 12-D distance <= r_c^2; the 12-D nearest if none is within.
  // The 7-D radius (about r_c) is far below 2 rho here: no sample is found by both searches.
  Evaluation nano7Evaluate(std::size_t qi) const {
    thread_local std::vector<std::pair<std::uint32_t, float>> hits;
    const double r2 = map.cutoffRadius() * map.cutoffRadius();
    std::size_t best = 0;
    double best_d2 = std::numeric_limits<double>::max();
    Mixture m;
    std::array<float, kBallDim> y = query7[qi];
    for (int sign = 0; sign < (query7_flip[qi] ? 2 : 1); ++sign) {
      if (sign == 1)
        for (int k = 3; k < kBallDim; ++k) y[k] = -y[k];
      hits.clear();
      nano7->radiusSearch(y.data(), radius7_2, hits, nanoflann::SearchParams(32, 0, false));
      for (const auto& h : hits) {
        const std::size_t g = grasp7[h.first];
        const double d2 = addTerm(qi, g, m, r2, rows7.data() + h.first * kEmbeddingDim);
        if (d2 <= r2 && (d2 < best_d2 || (d2 == best_d2 && g < best))) {
          best_d2 = d2;
          best = g;
        }
      }
    }
    if (best_d2 > r2) {
      nanoflann::KNNResultSet<double, std::size_t> rs(1);
      rs.init(&best, &best_d2);
      nano->findNeighbors(rs, query_embedding[qi].data(), nanoflann::SearchParams());
    }
    return finish(qi, best, best_d2, m);
  }

  std::size_t bruteNearest(std::size_t qi, double* d2_out) const {
    const double* q = query_embedding[qi].data();
    std::size_t best = 0;
    double best_d2 = std::numeric_limits<double>::max();
    for (std::size_t i = 0; i < map.size(); ++i) {
      const double* p = cloud.v.data() + i * kEmbeddingDim;
      double d2 = 0;
      for (int k = 0; k < kEmbeddingDim; ++k) d2 += (p[k] - q[k]) * (p[k] - q[k]);
      if (d2 < best_d2) {
        best_d2 = d2;
        best = i;
      }
    }
    *d2_out = best_d2;
    return best;
  }

  // One scan over every sample: the nearest and the full mixture.
  Evaluation bruteEvaluate(std::size_t qi) const {
    std::size_t best = 0;
    double best_d2 = std::numeric_limits<double>::max();
    Mixture m;
    for (std::size_t i = 0; i < map.size(); ++i) {
      const double d2 = addTerm(qi, i, m);
      if (d2 < best_d2) {
        best_d2 = d2;
        best = i;
      }
    }
    return finish(qi, best, best_d2, m);
  }
};

Baselines::Baselines(const TaskMap& map, const std::vector<Pose>& queries)
    : impl_(std::make_unique<Impl>(map, queries)) {}
Baselines::~Baselines() = default;
Evaluation Baselines::nanoflann7(std::size_t query) const {
  return impl_->nano7Evaluate(query);
}
Evaluation Baselines::nanoflann12(std::size_t query) const {
  return impl_->nanoEvaluate(query);
}
Evaluation Baselines::brute(std::size_t query) const {
  return impl_->bruteEvaluate(query);
}
std::size_t Baselines::nearestNanoflann(std::size_t query) const {
  std::size_t best = 0;
  double d2 = 0;
  nanoflann::KNNResultSet<double, std::size_t> rs(1);
  rs.init(&best, &d2);
  impl_->nano->findNeighbors(rs, impl_->query_embedding[query].data(), nanoflann::SearchParams());
  return best;
}
std::size_t Baselines::nearestBrute(std::size_t query, double* d2) const {
  return impl_->bruteNearest(query, d2);
}

}  // namespace bench
}  // namespace taskmap
