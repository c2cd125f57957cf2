#include "incremental_hull.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace taskmap {
namespace detail {

namespace {

constexpr int kMaxPoints = 1 << 16;
constexpr std::size_t kKeptFacets = 1 << 15;  // facets (about 5 MB) a reused hull may keep  //
                                              // sub-ridge keys pack four 16-bit point indices

/// Key of the 4 points of a new facet other than slot `skip` (0..4) and slot 5 (the apex).
/// Slots 0..4 are sorted, so the key needs no sorting.
std::uint64_t subRidgeKey(const std::array<int, 6>& vertex, int skip) {
  std::uint64_t key = 0;
  int shift = 0;
  for (int l = 0; l < 5; ++l) {
    if (l == skip) continue;
    key |= static_cast<std::uint64_t>(vertex[static_cast<std::size_t>(l)]) << shift;
    shift += 16;
  }
  return key;
}

/// Determinant of a 6 x 6 matrix by Gaussian elimination with partial pivoting (overwrites m).
/// Fixed-size loops: several times faster than a general LU for the many facets of a hull.
double determinant6(double (&m)[6][6]) {
  double det = 1.0;
  for (int c = 0; c < 6; ++c) {
    int pivot = c;
    for (int r = c + 1; r < 6; ++r) {
      if (std::abs(m[r][c]) > std::abs(m[pivot][c])) pivot = r;
    }
    if (m[pivot][c] == 0.0) return 0.0;
    if (pivot != c) {
      for (int k = c; k < 6; ++k) std::swap(m[pivot][k], m[c][k]);
      det = -det;
    }
    det *= m[c][c];
    const double inv = 1.0 / m[c][c];
    for (int r = c + 1; r < 6; ++r) {
      const double factor = m[r][c] * inv;
      for (int k = c + 1; k < 6; ++k) m[r][k] -= factor * m[c][k];
    }
  }
  return det;
}

}  // namespace

void IncrementalHull::reset(const Points& points, double tolerance) {
  points_ = &points;
  tolerance_ = tolerance;
  // Keep the buffers of ordinary grasps, but give back the memory of an exceptional one.
  if (facets_.capacity() > kKeptFacets) std::vector<Facet>().swap(facets_);
  facets_.clear();
  alive_.clear();
  free_.clear();
  stamp_ = 0;
  inserted_ = 0;
  created_total_ = 0;
  failure_ = "";
}

bool IncrementalHull::initSimplex() {
  const Eigen::Index n = points_->cols();
  if (n < kDim + 1 || n >= kMaxPoints) return fail("too few or too many points");
  is_vertex_.assign(static_cast<std::size_t>(n), 0);
  const Vec mean = points_->rowwise().mean();
  Eigen::Index first = 0;
  (points_->colwise() - mean).colwise().squaredNorm().maxCoeff(&first);
  // Greedy spread: each next point is the one farthest from the affine hull of those chosen.
  // residual.col(i) is point i minus the first, minus its projection on the chosen directions
  // (updated by one projection per step; the chosen direction is re-orthogonalised).
  std::array<int, kDim + 1> chosen{};
  chosen[0] = static_cast<int>(first);
  Points residual = points_->colwise() - points_->col(first);
  Eigen::Matrix<double, kDim, kDim> basis;
  for (int k = 1; k <= kDim; ++k) {
    Eigen::Index best_i = 0;
    const double best2 = residual.colwise().squaredNorm().maxCoeff(&best_i);
    if (!(best2 > 1e6 * tolerance_ * tolerance_)) return fail("points are flat");
    Vec dir = residual.col(best_i);
    for (int l = 0; l < k - 1; ++l) dir -= basis.col(l).dot(dir) * basis.col(l);
    const double norm = dir.norm();
    if (!(norm > 1e3 * tolerance_)) return fail("points are flat");
    dir /= norm;
    basis.col(k - 1) = dir;
    chosen[static_cast<std::size_t>(k)] = static_cast<int>(best_i);
    residual -= dir * (dir.transpose() * residual);
  }
  interior_.setZero();
  for (int c : chosen) interior_ += points_->col(c);
  interior_ /= kDim + 1;

  facets_.clear();
  alive_.clear();
  free_.clear();
  for (int i = 0; i <= kDim; ++i) {
    const int f = newFacet();
    Facet& facet = facets_[static_cast<std::size_t>(f)];
    int slot = 0;
    for (int j = 0; j <= kDim; ++j) {
      if (j == i) continue;
      facet.vertex[static_cast<std::size_t>(slot)] = chosen[static_cast<std::size_t>(j)];
      facet.neighbor[static_cast<std::size_t>(slot)] = j;  // facet j omits chosen[j]
      ++slot;
    }
    if (!hyperplane(facet.vertex, facet.normal, facet.offset)) return false;
  }
  for (int c : chosen) is_vertex_[static_cast<std::size_t>(c)] = 1;
  inserted_ = kDim + 1;
  return true;
}

bool IncrementalHull::hyperplane(const std::array<int, kDim>& vertex, Vec& normal_out,
                                 double& offset_out) const {
  const Vec base = points_->col(vertex[kDim - 1]);
  Eigen::Matrix<double, kDim, kDim - 1> basis;
  for (int j = 0; j < kDim - 1; ++j) {
    Vec a = points_->col(vertex[static_cast<std::size_t>(j)]) - base;
    for (int pass = 0; pass < 2; ++pass) {
      for (int l = 0; l < j; ++l) a -= basis.col(l).dot(a) * basis.col(l);
    }
    const double norm = a.norm();
    if (!(norm > tolerance_)) return fail("facet vertices affinely dependent");
    basis.col(j) = a / norm;
  }
  // The coordinate axis least represented in the span leaves a residual of norm >= 1/sqrt(6).
  Eigen::Index axis = 0;
  basis.rowwise().squaredNorm().minCoeff(&axis);
  Vec normal = Vec::Unit(axis);
  for (int pass = 0; pass < 2; ++pass) normal -= basis * (basis.transpose() * normal);
  normal.normalize();
  double offset = 0.0;
  for (int v : vertex) offset += normal.dot(points_->col(v));
  offset /= kDim;
  for (int v : vertex) {
    if (std::abs(normal.dot(points_->col(v)) - offset) > tolerance_)
      return fail("facet vertex off its hyperplane");
  }
  const double side = normal.dot(interior_) - offset;
  if (std::abs(side) <= tolerance_ || !std::isfinite(side))
    return fail("interior point on a facet hyperplane");
  if (side > 0.0) {
    normal = -normal;
    offset = -offset;
  }
  normal_out = normal;
  offset_out = offset;
  return true;
}

bool IncrementalHull::rotateHyperplane(Planned& p, const Facet& visible, const Facet& outer) const {
  // The hyperplanes of `visible` and `outer` both contain the horizon ridge; so does every
  // combination a n_u - b n_v. With a, b the apex's distances to them, the combination
  // (a n_u - b n_v) . x = a o_u - b o_v also passes through the apex, and it points outward
  // (a > 0 >= b up to the tolerance).
  const int apex = p.vertex[kDim - 1];
  const double a = distance(visible, apex);
  const double b = distance(outer, apex);
  Vec normal = a * outer.normal - b * visible.normal;
  const double norm = normal.norm();
  if (!(norm > 0.0)) return false;
  normal /= norm;
  const double offset = (a * outer.offset - b * visible.offset) / norm;
  for (int v : p.vertex) {
    if (std::abs(normal.dot(points_->col(v)) - offset) > 0.5 * tolerance_) return false;
  }
  const double side = normal.dot(interior_) - offset;
  if (!(side < -tolerance_)) return false;
  p.normal = normal;
  p.offset = offset;
  return true;
}

int IncrementalHull::newFacet() {
  ++created_total_;
  int f;
  if (!free_.empty()) {
    f = free_.back();
    free_.pop_back();
    Facet& facet = facets_[static_cast<std::size_t>(f)];
    facet.outside.clear();
    facet.tested = 0;
    facet.visible = false;
  } else {
    f = static_cast<int>(facets_.size());
    facets_.emplace_back();
  }
  facets_[static_cast<std::size_t>(f)].alive_slot = static_cast<int>(alive_.size());
  alive_.push_back(f);
  return f;
}

void IncrementalHull::kill(int f) {
  Facet& facet = facets_[static_cast<std::size_t>(f)];
  const int slot = facet.alive_slot;
  const int last = alive_.back();
  alive_[static_cast<std::size_t>(slot)] = last;
  facets_[static_cast<std::size_t>(last)].alive_slot = slot;
  alive_.pop_back();
  facet.alive_slot = -1;
  free_.push_back(f);
}

bool IncrementalHull::addPoint(int i, int seen) {
  if (is_vertex_[static_cast<std::size_t>(i)]) return fail("point already a vertex");
  if (distance(facets_[static_cast<std::size_t>(seen)], i) <= tolerance_) {
    return fail("point not beyond the facet");
  }
  // Facets within the tolerance of the new point (coplanar) stay first; if that leaves a
  // horizon that round-off makes non-convex or non-manifold, they are replaced too.
  if (!plan(i, seen, false) && !plan(i, seen, true)) return false;
  commit(i);
  return true;
}

bool IncrementalHull::plan(int i, int seen, bool replace_coplanar) {
  ++stamp_;
  const double visible_above = replace_coplanar ? -tolerance_ : tolerance_;
  visible_.clear();
  planned_.clear();
  {
    Facet& s = facets_[static_cast<std::size_t>(seen)];
    s.tested = stamp_;
    s.visible = true;
  }
  visible_.push_back(seen);
  for (std::size_t q = 0; q < visible_.size(); ++q) {
    const int v = visible_[q];
    for (int k = 0; k < kDim; ++k) {
      const int u = facets_[static_cast<std::size_t>(v)].neighbor[static_cast<std::size_t>(k)];
      Facet& fu = facets_[static_cast<std::size_t>(u)];
      if (fu.tested != stamp_) {
        fu.tested = stamp_;
        fu.visible = distance(fu, i) > visible_above;
        if (fu.visible) visible_.push_back(u);
      }
      if (fu.visible) continue;
      // Horizon ridge: facet v without its slot k. New facet: the ridge's 5 points, sorted
      // (slots 0..4), and the apex i (slot 5), whose neighbour across slot 5 is u.
      const Facet& fv = facets_[static_cast<std::size_t>(v)];
      Planned p;
      int c = 0;
      for (int l = 0; l < kDim; ++l) {
        if (l != k)
          p.vertex[static_cast<std::size_t>(c++)] = fv.vertex[static_cast<std::size_t>(l)];
      }
      std::sort(p.vertex.begin(), p.vertex.begin() + (kDim - 1));
      p.vertex[kDim - 1] = i;
      p.outer = u;
      p.back = -1;
      for (int l = 0; l < kDim; ++l) {
        if (fu.neighbor[static_cast<std::size_t>(l)] == v) p.back = l;
      }
      if (p.back < 0) return fail("broken adjacency");
      if (std::abs(distance(fu, i)) <= tolerance_) {
        // The apex lies on u's hyperplane (and so does the ridge): the new facet continues u
        // in the same hyperplane. Sharing u's plane exactly keeps later visibility tests of
        // the two consistent, where a plane fitted through the thin new simplex would tilt.
        p.normal = fu.normal;
        p.offset = fu.offset;
      } else if (!rotateHyperplane(p, fv, fu) && !hyperplane(p.vertex, p.normal, p.offset)) {
        return false;
      }
      // Convexity across the horizon: the outer facet's opposite vertex is not beyond it.
      const int opposite = fu.vertex[static_cast<std::size_t>(p.back)];
      if (p.normal.dot(points_->col(opposite)) - p.offset > tolerance_) {
        return fail("non-convex horizon");
      }
      planned_.push_back(p);
    }
  }
  // New facets meet along ridges through the apex: each sub-ridge (a horizon ridge without
  // one point) must be shared by exactly two new facets. Match them in an open-addressing table.
  std::size_t table_size = 16;
  while (table_size < 2 * (kDim - 1) * planned_.size()) table_size *= 2;
  subridges_.assign(table_size, SubRidge{0, -1, -1});
  int unmatched = 0;
  for (std::size_t n = 0; n < planned_.size(); ++n) {
    Planned& p = planned_[n];
    for (int j = 0; j < kDim - 1; ++j) {
      const std::uint64_t key = subRidgeKey(p.vertex, j);
      std::size_t slot =
          static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 40) & (table_size - 1);
      while (true) {
        SubRidge& e = subridges_[slot];
        if (e.slot < 0) {  // empty: first occurrence
          e = SubRidge{key, static_cast<int>(n), j};
          ++unmatched;
          break;
        }
        if (e.key == key) {
          if (e.facet < 0) return fail("sub-ridge on three facets");
          planned_[static_cast<std::size_t>(e.facet)].neighbor[static_cast<std::size_t>(e.slot)] =
              static_cast<int>(n);
          p.neighbor[static_cast<std::size_t>(j)] = e.facet;
          e.facet = -1;  // matched
          --unmatched;
          break;
        }
        slot = (slot + 1) & (table_size - 1);
      }
    }
  }
  if (unmatched != 0) return fail("unmatched sub-ridge");
  return true;
}

void IncrementalHull::commit(int i) {
  created_.clear();
  for (std::size_t n = 0; n < planned_.size(); ++n) created_.push_back(newFacet());
  for (std::size_t n = 0; n < planned_.size(); ++n) {
    const Planned& p = planned_[n];
    const int id = created_[n];
    Facet& f = facets_[static_cast<std::size_t>(id)];
    f.vertex = p.vertex;
    f.normal = p.normal;
    f.offset = p.offset;
    for (int j = 0; j < kDim - 1; ++j) {
      f.neighbor[static_cast<std::size_t>(j)] =
          created_[static_cast<std::size_t>(p.neighbor[static_cast<std::size_t>(j)])];
    }
    f.neighbor[kDim - 1] = p.outer;
    facets_[static_cast<std::size_t>(p.outer)].neighbor[static_cast<std::size_t>(p.back)] = id;
  }
  // Outside sets of the deleted facets move to the first new facet they lie beyond (a point
  // outside the new hull lies beyond one of the new facets); the others are now inside.
  for (int v : visible_) {
    std::vector<int>& out = facets_[static_cast<std::size_t>(v)].outside;
    for (int p : out) {
      if (p == i) continue;
      for (int nf : created_) {
        if (distance(facets_[static_cast<std::size_t>(nf)], p) > tolerance_) {
          facets_[static_cast<std::size_t>(nf)].outside.push_back(p);
          break;
        }
      }
    }
    out.clear();
  }
  for (int v : visible_) kill(v);
  is_vertex_[static_cast<std::size_t>(i)] = 1;
  ++inserted_;
}

bool IncrementalHull::complete() {
  const Eigen::Index n = points_->cols();
  for (int f : alive_) facets_[static_cast<std::size_t>(f)].outside.clear();
  for (Eigen::Index p = 0; p < n; ++p) {
    if (is_vertex_[static_cast<std::size_t>(p)]) continue;
    for (int f : alive_) {
      if (distance(facets_[static_cast<std::size_t>(f)], static_cast<int>(p)) > tolerance_) {
        facets_[static_cast<std::size_t>(f)].outside.push_back(static_cast<int>(p));
        break;
      }
    }
  }
  // Quickhull order: repeatedly the farthest outside point of some facet with outside points.
  for (int guard = 0; guard <= n; ++guard) {
    int seen = -1;
    for (int f : alive_) {
      if (!facets_[static_cast<std::size_t>(f)].outside.empty()) {
        seen = f;
        break;
      }
    }
    if (seen < 0) return true;
    const Facet& s = facets_[static_cast<std::size_t>(seen)];
    int far = s.outside.front();
    double far_d = -std::numeric_limits<double>::infinity();
    for (int p : s.outside) {
      const double d = distance(s, p);
      if (d > far_d) {
        far_d = d;
        far = p;
      }
    }
    if (!addPoint(far, seen)) return false;
  }
  return fail("too many insertions");
}

int IncrementalHull::nearestFacet() const {
  int best = alive_.front();
  for (int f : alive_) {
    if (facets_[static_cast<std::size_t>(f)].offset <
        facets_[static_cast<std::size_t>(best)].offset) {
      best = f;
    }
  }
  return best;
}

double IncrementalHull::volume() const {
  double sum = 0.0;
  double m[kDim][kDim];
  for (int f : alive_) {
    const Facet& facet = facets_[static_cast<std::size_t>(f)];
    for (int k = 0; k < kDim; ++k) {
      const auto v = points_->col(facet.vertex[static_cast<std::size_t>(k)]);
      for (int r = 0; r < kDim; ++r) m[r][k] = v(r) - interior_(r);
    }
    sum += std::abs(determinant6(m));
  }
  return sum / 720.0;  // 6!
}

}  // namespace detail
}  // namespace taskmap
