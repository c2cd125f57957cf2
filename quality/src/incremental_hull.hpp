#pragma once
// Private: a 6-D beneath-beyond convex hull over a fixed point set, grown one point at a time.
// It serves two callers in wrench_epsilon.cpp: the lazy refinement that finds force closure
// and epsilon while inserting only the points it needs (Zheng's support-function method), and
// the complete hull (Quickhull order with outside sets) for the volume.
//
// Facets are simplices of 6 points. A point within `tolerance` of a facet's hyperplane does not
// see it, so coplanar points (every contact's cone edges lie in one 2-flat) give several
// simplicial facets in one hyperplane, which is harmless for the distance and the volume.
// Every operation reports failure (precision or topology trouble) instead of asserting; the
// caller then falls back to qhull.
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace taskmap {
namespace detail {

class IncrementalHull {
 public:
  static constexpr int kDim = 6;
  using Vec = Eigen::Matrix<double, kDim, 1>;
  using Points = Eigen::Matrix<double, kDim, Eigen::Dynamic>;

  struct Facet {
    Vec normal = Vec::Zero();          ///< outward unit normal
    double offset = 0.0;               ///< normal . x = offset on the hyperplane (signed)
    std::array<int, kDim> vertex{};    ///< point indices
    std::array<int, kDim> neighbor{};  ///< facet across the ridge opposite vertex[k]
    int alive_slot = -1;               ///< position in alive_, -1 once deleted
    int tested = 0;                    ///< stamp of the last visibility test
    bool visible = false;              ///< result of that test
    std::vector<int> outside;          ///< complete(): points beyond this facet
  };

  IncrementalHull() = default;
  /// Starts over on `points` (6 x n, must outlive the use) with `tolerance`, the distance (same
  /// units) within which a point counts as on a hyperplane. Keeps the buffers' capacity, so one
  /// hull per thread serves many grasps without reallocating.
  void reset(const Points& points, double tolerance);

  /// Builds the starting simplex from 7 affinely independent points chosen greedily (largest
  /// spread). false when the points are flat within the tolerance or n >= 65536.
  bool initSimplex();

  /// Inserts point i, which lies beyond facet `seen` by more than the tolerance. false on a
  /// precision or topology failure (the hull is then unusable).
  bool addPoint(int i, int seen);

  /// Inserts every remaining point that lies outside (Quickhull order). false on failure.
  bool complete();

  /// The live facet with the smallest offset (nearest hyperplane to the origin, signed).
  int nearestFacet() const;

  /// 6-D volume: sum over facets of the simplex volume towards the interior point.
  double volume() const;

  const Facet& facet(int f) const { return facets_[static_cast<std::size_t>(f)]; }
  const std::vector<int>& aliveFacets() const { return alive_; }
  int insertedPoints() const { return inserted_; }
  /// Why the last failing operation failed ("" if none did).
  const char* failure() const { return failure_; }
  /// Facets created so far, the starting simplex included (a measure of the work done).
  int createdFacets() const { return created_total_; }

 private:
  double distance(const Facet& f, int point) const {
    return f.normal.dot(points_->col(point)) - f.offset;
  }
  /// A new facet worked out by plan() before anything changes.
  struct Planned {
    std::array<int, kDim> vertex{};    ///< sorted horizon ridge (slots 0..4), apex (slot 5)
    std::array<int, kDim> neighbor{};  ///< slots 0..4: index into planned_
    Vec normal = Vec::Zero();
    double offset = 0.0;
    int outer = -1;  ///< the old facet across slot 5
    int back = -1;   ///< the slot of `outer` that pointed at the deleted facet
  };
  /// Hyperplane through 6 points, oriented away from interior_. false if they are affinely
  /// dependent within the tolerance or a vertex ends up off the plane.
  bool hyperplane(const std::array<int, kDim>& vertex, Vec& normal, double& offset) const;
  /// Hyperplane of a planned facet from the two old hyperplanes through its horizon ridge;
  /// false when round-off puts a vertex off it (then hyperplane()).
  bool rotateHyperplane(Planned& p, const Facet& visible, const Facet& outer) const;
  /// Finds the facets point i replaces (visible: distance > tolerance, or > -tolerance with
  /// `replace_coplanar`) and plans the new ones; false (nothing changed) when the horizon is
  /// not a convex, manifold ring.
  bool plan(int i, int seen, bool replace_coplanar);
  /// Applies the last successful plan for point i.
  void commit(int i);
  int newFacet();
  bool fail(const char* why) const {
    failure_ = why;
    return false;
  }
  void kill(int f);

  const Points* points_ = nullptr;
  double tolerance_ = 0.0;
  Vec interior_ = Vec::Zero();  ///< centroid of the starting simplex (inside every later hull)
  std::vector<Facet> facets_;
  std::vector<int> alive_;
  std::vector<int> free_;
  std::vector<char> is_vertex_;
  int stamp_ = 0;
  int inserted_ = 0;
  int created_total_ = 0;
  mutable const char* failure_ = "";
  // Scratch buffers of addPoint, kept to avoid reallocation.
  struct SubRidge {
    std::uint64_t key;
    int facet;
    int slot;
  };
  std::vector<int> visible_;
  std::vector<Planned> planned_;
  std::vector<SubRidge> subridges_;
  std::vector<int> created_;
};

}  // namespace detail
}  // namespace taskmap
