#pragma once
// Private to grasp_sim: the object as a static Bullet triangle mesh (BVH) and the hand links as
// convex Bullet shapes. Bullet types stay in collision_scene.cpp. Const methods are thread-safe:
// queries run Bullet's stateless GJK/EPA (btGjkEpaSolver2) on the triangles the BVH reports,
// all state on the stack; the shapes and the BVH are shared read-only.

#include <cstddef>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/core/triangle_mesh.hpp"
#include "taskmap/hands/hand_model.hpp"

namespace taskmap {

/// Closest-feature result of a link against one object triangle.
struct TriangleHit {
  double distance = 0.0;                              ///< signed, metres; < 0 is penetration depth
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    ///< witness point on the object triangle
  int triangle = -1;                                  ///< triangle index in the mesh
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< separation direction, object -> link
};

/// Which exact hits CollisionScene::linkNearest considers: a triangle whose outward normal n
/// satisfies n . away < -opposing (unless any_direction), hit with a separation direction whose
/// dot product with n is >= min_agreement.
struct FacingFilter {
  Eigen::Vector3d away = Eigen::Vector3d::UnitZ();  ///< unit direction (object frame)
  double opposing = 0.5;                            ///< cosine bound on n . away
  double min_agreement = 0.5;                       ///< cosine bound on the hit normal
  bool any_direction = false;                       ///< true: no condition on n . away
  /// True when a triangle with outward normal `n` is considered (whatever its hit).
  bool faces(const Eigen::Vector3d& n) const { return any_direction || n.dot(away) < -opposing; }
  /// True when the hit `h` on a triangle with outward normal `n` passes.
  bool passes(const Eigen::Vector3d& n, const TriangleHit& h) const {
    return faces(n) && h.normal.dot(n) >= min_agreement;
  }
};

/// What the overlap question of a link of one box saw (CollisionScene::linkDistance with
/// `seen`): every triangle the separating axes put within the threshold, with its gap and leaf
/// node, from a walk that met no overlap (`complete`; also when the link is beyond the object's
/// box: none). Every hit linkNearest could report at the same pose and threshold is among them,
/// so it reads them instead of searching the tree.
struct SeenTriangles {
  /// One triangle within the threshold.
  struct Near {
    double gap;    ///< separating-axis gap, metres (a lower bound of the distance)
    int triangle;  ///< index in the mesh
    int node;      ///< its leaf in Bullet's tree
  };
  bool complete = false;                                   ///< `near` holds every such triangle
  int link = -1;                                           ///< the link asked about
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< the link's pose, object frame
  double threshold = 0.0;                                  ///< the question's, metres
  std::vector<Near> near;                                  ///< by gap, then triangle
  /// True when this is the complete record of `link`'s question at `pose` (bit for bit) and
  /// `threshold`.
  bool answers(int link_asked, const Eigen::Isometry3d& pose_asked, double threshold_asked) const {
    return complete && link == link_asked && threshold == threshold_asked &&
           pose.matrix() == pose_asked.matrix();
  }
};

/// Returned by CollisionScene::linkDistance for an overlapping link (depth not computed).
constexpr double kOverlapping = -1e-300;

class CollisionScene {
 public:
  /// How link-versus-object queries find their triangles. Both give the same results bit for
  /// bit (same triangles, same order, same GJK/EPA calls on the ones that matter).
  enum class Mode {
    kBullet,  ///< Bullet's BVH, every triangle in the shape's padded bounding box (baseline)
    kCulled,  ///< Bullet's tree walked with the link shape's planes (culled_query.cpp)
    kAuto,    ///< kCulled for hull shapes, and for every shape from kCulledMinFaces faces on
  };
  /// Below this many faces Bullet's box query meets few triangles and, for boxes, cylinders
  /// and spheres, the planes cost more than they save (measured with tests/bench/grasp_sim on
  /// the 172-face basket and 256-face cylinder; hulls gain 3x there).
  static constexpr std::size_t kCulledMinFaces = 1000;
  /// Builds the BVH of `mesh` and a convex shape for every collision shape of `hand`. With
  /// `separating_axis_contacts`, on a mesh whose boxes take culled queries (kCulled, or kAuto from
  /// kCulledMinFaces faces), linkHits takes the penetration of a box link shape and a triangle
  /// from the 13 separating axes (boxTrianglePenetration), and of a hull from its face planes
  /// where they prove it (ShapePlanes::faceContact), instead of EPA.
  CollisionScene(const TriangleMesh& mesh, const HandModel& hand, Mode mode = Mode::kAuto,
                 bool separating_axis_contacts = false);
  ~CollisionScene();
  CollisionScene(const CollisionScene&) = delete;
  CollisionScene& operator=(const CollisionScene&) = delete;

  /// Minimum signed distance between link `link` at pose `t` (object frame) and the object,
  /// considering triangles within `threshold` metres; +infinity when none is that close. When
  /// the link overlaps a triangle the search stops and a negative value is returned: minus a
  /// lower bound of the link's penetration depth (the box-triangle SAT depth of the first
  /// overlapping triangle, or kOverlapping when unknown). Use linkHits for exact depths.
  double linkDistance(int link, const Eigen::Isometry3d& t, double threshold) const;
  /// linkDistance, recording in *seen what a link of one box saw (seen->complete false for
  /// other links and when the walk stopped at an overlap).
  double linkDistance(int link, const Eigen::Isometry3d& t, double threshold,
                      SeenTriangles* seen) const;
  /// Like linkDistance but exact: every triangle within `threshold` is appended to `hits`
  /// with its signed distance (EPA depth when penetrating; when the scene was built with
  /// separating_axis_contacts, the 13-axis depth for boxes and the face depth for hulls where
  /// their face planes prove it) and witness point; returns the minimum signed distance.
  double linkHits(int link, const Eigen::Isometry3d& t, double threshold,
                  std::vector<TriangleHit>* hits) const;
  /// True when linkHits(link, t, threshold) would hold a hit deeper than `depth` (metres, > 0)
  /// whose normal has a dot product >= `min_agreement` with its face normal; EPA runs only on
  /// triangles whose depth bound exceeds `depth` (lean_query.cpp).
  bool linkPressesDeeper(int link, const Eigen::Isometry3d& t, double threshold, double depth,
                         double min_agreement) const;
  /// The smallest signed distance over the hits linkHits(link, t, threshold) would return that
  /// pass `filter` (every hit when null), +infinity when none; computed by branch and bound
  /// without the other hits (lean_query.cpp). With `hit`, also the first hit in linkHits' order
  /// with that distance (unchanged when none).
  double linkNearest(int link, const Eigen::Isometry3d& t, double threshold,
                     const FacingFilter* filter, TriangleHit* hit = nullptr) const;
  /// linkNearest, the same answer; from `seen` instead of the tree when it is complete and was
  /// recorded for this link at the same pose (bit for bit) and threshold.
  double linkNearest(int link, const Eigen::Isometry3d& t, double threshold,
                     const FacingFilter* filter, TriangleHit* hit, const SeenTriangles& seen) const;
  /// True when some shape of `link` at pose `t` lies wholly inside the object (ray parity from
  /// the shape's centre); call only for links that touch no triangle.
  bool linkInside(int link, const Eigen::Isometry3d& t) const;
  /// The centre (object frame, metres) of the sphere enclosing link `link` at pose `t`, of radius
  /// linkRadius(link). linkLinkDistance returns +infinity when two links' spheres are farther
  /// apart than their radii plus the threshold (the same arithmetic: a caller may test it first).
  Eigen::Vector3d linkCentre(int link, const Eigen::Isometry3d& t) const;
  /// True when link `link` at pose `t` (object frame), moved along the unit direction `dir` by
  /// any distance u >= 0, stays farther than `gap` metres from the object: for the object's box,
  /// or every box of the object's tree down to the triangles, either the line of its link box's
  /// centre (a box holding every shape of the link) misses it grown on every axis by the link
  /// box's extent along it plus `gap`, or one of 6 axes separates it from the link box itself
  /// swept along the line and grown by `gap` (the box's axes and each crossed with `dir`; for a
  /// triangle also its normal). False when it cannot tell.
  bool linkSweepClear(int link, const Eigen::Isometry3d& t, const Eigen::Vector3d& dir,
                      double gap) const;
  /// The same bound as a distance: a u beyond which link `link`, moved from pose `t` along
  /// `dir` by any further distance, stays farther than `gap` metres from the object; negative
  /// when it does for every u >= 0 (linkSweepClear). With `first` any u >= 0 once it cannot
  /// tell (cheaper: what linkSweepClear asks).
  double linkSweepLast(int link, const Eigen::Isometry3d& t, const Eigen::Vector3d& dir, double gap,
                       bool first = false) const;
  /// Radius of the sphere enclosing link `link` (pose independent), metres.
  double linkRadius(int link) const;
  /// Minimum signed distance between two links at their poses, within `threshold`
  /// (+infinity beyond). With `axis` (a unit direction in link a's frame, or zero; used only when
  /// a shape of either link is a hull, ignored otherwise): when the two links' extents along it
  /// leave a gap above threshold + 1e-9 m, +infinity without GJK (the same answer: the gap is a
  /// lower bound of the distance); otherwise GJK/EPA as without it, and *axis becomes the
  /// direction from a's witness to b's of the nearest separated shape pair (unchanged when every
  /// pair overlaps). A caller keeps one per link pair across poses. With `apart`: set true when
  /// the answer (+infinity) came from the bounding spheres or the axis's gap, without GJK (then
  /// the same call with a and b swapped answers +infinity too), false otherwise.
  double linkLinkDistance(int a, const Eigen::Isometry3d& ta, int b, const Eigen::Isometry3d& tb,
                          double threshold, Eigen::Vector3d* axis = nullptr,
                          bool* apart = nullptr) const;
  /// Outward unit normal of triangle `tri`.
  const Eigen::Vector3d& faceNormal(int tri) const;
  /// Centre and radius of a sphere enclosing the object, metres.
  const Eigen::Vector3d& objectCentre() const;
  double objectRadius() const;

  /// Bullet-side data (collision_data.hpp; opaque outside it).
  struct Data;

 private:
  std::unique_ptr<Data> d_;
};

}  // namespace taskmap
