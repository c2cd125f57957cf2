#pragma once
// Private to grasp_sim (included by collision_scene.cpp and culled_query.cpp only): the Bullet
// shapes and the object data behind CollisionScene, and the two query paths.

#include <array>
#include <limits>
#include <memory>
#include <vector>

#include <BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h>
#include <BulletCollision/CollisionShapes/btConvexShape.h>
#include <BulletCollision/CollisionShapes/btTriangleIndexVertexArray.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpa2.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "collision_scene.hpp"
#include "taskmap/core/constants.hpp"

namespace taskmap {

inline btVector3 bt(const Eigen::Vector3d& v) {
  return btVector3(v.x(), v.y(), v.z());
}
inline Eigen::Vector3d eig(const btVector3& v) {
  return Eigen::Vector3d(v.x(), v.y(), v.z());
}

inline btTransform bt(const Eigen::Isometry3d& t) {
  const Eigen::Matrix3d& r = t.linear();
  btMatrix3x3 m(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2));
  return btTransform(m, bt(Eigen::Vector3d(t.translation())));
}

/// Signed distance between two convex shapes with GJK (separated) or EPA (overlapping).
/// Returns false when the depth of an overlap is not wanted (`need_depth` false) or EPA failed;
/// `r` then holds what is known. Distances are between the full shapes (margins included).
bool signedDistance(const btConvexShape* a, const btTransform& ta, const btConvexShape* b,
                    const btTransform& tb, bool need_depth, double* distance,
                    btGjkEpaSolver2::sResults* r, bool* overlap);

/// Runs GJK/EPA of one convex shape against every triangle the BVH reports near it.
struct TriangleQuery : btTriangleCallback {
  const btConvexShape* shape = nullptr;
  btTransform xf;
  double threshold = 0.0;
  bool exact = false;  // EPA depth and witnesses for overlapping triangles
  std::vector<TriangleHit>* hits = nullptr;
  double min_distance = std::numeric_limits<double>::infinity();
  bool overlap_found = false;

  // Boxes: the separating-axis test decides far and overlapping triangles without GJK.
  bool is_box = false;
  // The test stops at the first axis beyond the threshold (false in the baseline, which keeps
  // the code it had: all 13 axes).
  bool sat_early_exit = true;
  // Exact queries take penetrations from separating axes, not EPA (queryLinkCulled with
  // sat_depths, for shapes with ShapeEntry::sat_depths): a box's from the 13 axes
  // (processTriangle), a hull's from its face planes where they prove it (walkAll).
  bool sat_depths = false;
  Eigen::Vector3d box_centre, box_half;
  Eigen::Matrix3d box_axes;

  void processTriangle(btVector3* tri, int part, int index) override;
};

/// Contacts by separating axes (sat_depths): pairs overlapping by more than this (metres) take
/// the axes' depth; shallower ones GJK/EPA as before.
constexpr double kSatDepthMin = 1e-9;

/// Culling planes are tested in blocks of this many (vector arithmetic, early exit per block).
constexpr int kPlaneBlock = 8;

struct ShapeEntry {
  std::unique_ptr<btConvexShape> shape;
  Eigen::Isometry3d origin;  // shape frame in the link frame
  double bounding_radius = 0.0;
  bool is_box = false;
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();
  /// Boxes and hulls on meshes whose boxes take culled queries (Data::culled_boxes), with
  /// GraspSimDiagnostics::separating_axis_contacts: CollisionScene::linkHits takes their
  /// penetration depths and witnesses from separating axes instead of EPA (boxTrianglePenetration,
  /// ShapePlanes::faceContact).
  bool sat_depths = false;
  // Culled queries: separating planes of the shape in its frame, max over the shape of
  // (px[i], py[i], pz[i]) . x is pr[i] (a point set beyond any one plane by g is at least g
  // away), as columns for vector arithmetic. Boxes: their 6 faces; hulls: a 26-DOP, then their
  // own face planes (an inside test for points, from facet_begin on); cylinders and spheres: a
  // 26-DOP. Triangles are tested on the DOP and, for hulls, on planes along a spread subset of
  // the face normals (at their support, so as valid). Each group is padded to a multiple of
  // kPlaneBlock with planes that never separate (normal 0, reach +inf).
  Eigen::ArrayXd px, py, pz, pr;
  int node_planes = 0;  ///< planes [0..node_planes) are tested on tree nodes
  /// Planes [0..facet_begin) are tested on triangles; hulls: [facet_begin..] are the hull's
  /// face planes (exact-hit walks and the inside test).
  int facet_begin = 0;
  bool is_hull = false;
  /// Hulls: the face planes come in blocks of kPlaneBlock with close normals (addCullingData
  /// groups them); per block, in the shape frame, a unit axis (bx, by, bz), the largest |n - axis|
  /// over its normals (bchord) and its smallest reach (bmin), so that for any point p (shape
  /// frame) and face i of the block n_i . p - pr_i <= axis . p + |p| chord - bmin.
  Eigen::ArrayXd bx, by, bz, bchord, bmin;
  /// Per face plane from facet_begin: its place in the hull computation's face order (ties
  /// between faces go to the earlier there, as before the grouping); padding: INT_MAX.
  std::vector<int> face_rank;
};

struct CollisionScene::Data {
  std::vector<double> vertices;
  std::vector<int> indices;
  std::unique_ptr<btTriangleIndexVertexArray> arrays;
  std::unique_ptr<btBvhTriangleMeshShape> mesh_shape;
  std::vector<Eigen::Vector3d> normals;
  Eigen::Vector3d lo, hi, centre;
  double radius = 0.0;
  std::vector<std::vector<ShapeEntry>> links;
  std::vector<Eigen::Vector3d> link_centre;  // bounding sphere of each link, link frame
  std::vector<double> link_radius;
  // Per link: a box in the link frame holding all its shapes (margins included): centre, half
  // extents (zero for a link without shapes). CollisionScene::linkSweepClear.
  std::vector<std::array<Eigen::Vector3d, 2>> link_box;
  // Culled queries (CollisionScene::Mode::kCulled) walk Bullet's tree with their own node test
  // and read the triangle corners from here.
  bool culled = false;
  bool culled_boxes = false;  // boxes, cylinders and spheres too (else hulls only; kAuto)
  std::vector<std::array<Eigen::Vector3d, 3>> corners;
  // The boxes of the nodes of Bullet's quantized tree, unquantized once (lo, hi), node order.
  std::vector<std::array<Eigen::Vector3d, 2>> node_boxes;
  // A cone holding the outward normals of each node's triangles: unit axis, half angle
  // (radians, pi or more: every direction), node order.
  struct NormalCone {
    Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
    double half = 0.0;
    double cos_half = 1.0, sin_half = 0.0;
  };
  std::vector<NormalCone> node_cones;
};

/// The baseline's cull of one shape: its bounding sphere (centre at `ts`, object frame) is
/// farther than `threshold` (metres) from the object's bounding box.
inline bool beyondObjectBox(const CollisionScene::Data& d, const ShapeEntry& e,
                            const Eigen::Isometry3d& ts, double threshold) {
  const Eigen::Vector3d c = ts.translation();
  const Eigen::Vector3d out = (d.lo - c).cwiseMax(c - d.hi).cwiseMax(0.0);
  return out.norm() > e.bounding_radius + threshold;
}

/// Separating-axis bound between an oriented box (centre c, unit axes as the columns of r, half
/// extents e) and a triangle: the largest separation over the 13 axes of the box-triangle SAT.
/// A value > 0 is a lower bound on their distance; a value <= 0 means they intersect (the 13
/// axes are complete for a box and a triangle). Stops at the first axis that puts the
/// separation above `limit` (the value returned is then some value > limit; at or below it, it
/// is the full maximum).
double boxTriangleSeparation(const Eigen::Vector3d& c, const Eigen::Matrix3d& r,
                             const Eigen::Vector3d& e, const btVector3* tri,
                             double limit = std::numeric_limits<double>::infinity());
/// The separation of an oriented box (centre c, unit axes as the columns of r, half extents e)
/// and a triangle and, when they overlap, their penetration, object frame.
struct BoxTrianglePenetration {
  double separation = 0.0;  ///< boxTriangleSeparation's value (no limit), the same bits
  /// The rest only when separation < 0:
  double depth = 0.0;  ///< the smallest overlap over the 13 axes, metres (exact for the pair)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< unit, separates them: object -> box
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    ///< witness on the triangle
};
/// The 13-axis separation and penetration of a box and a triangle: the axis of smallest overlap
/// (a box face, then the triangle's normal, preferred at ties within 1e-12 m); the witness
/// is the triangle's deepest feature on that axis (a corner, or the centre of a tied edge or
/// face clipped to the box's feature), the box's deepest corner or feature moved onto the
/// triangle, or the closest point of the triangle's edge to the box's edge.
BoxTrianglePenetration boxTrianglePenetration(const Eigen::Vector3d& c, const Eigen::Matrix3d& r,
                                              const Eigen::Vector3d& e, const btVector3* tri);
/// A TriangleQuery of shape `e` at pose `ts` (object frame).
TriangleQuery makeTriangleQuery(const ShapeEntry& e, const Eigen::Isometry3d& ts, double threshold,
                                bool exact, std::vector<TriangleHit>* hits);
/// Adds the culling data (k-DOP, facets) of `e` built from its Bullet shape and, for a hull,
/// its points.
void addCullingData(const std::vector<Eigen::Vector3d>& hull_points, ShapeEntry* e);
/// Prepares `d` for culled queries (triangle corners) of hull shapes, and of every shape when
/// `all_shapes`.
void buildCulling(const std::vector<Eigen::Vector3d>& vertices,
                  const std::vector<Eigen::Vector3i>& faces, bool all_shapes,
                  CollisionScene::Data* d);
/// The object's part of `d` from `mesh`: vertex and index arrays, face normals, bounds and
/// Bullet's quantized tree (margin 0). Throws Error when a face indexes a missing vertex.
void buildObjectTree(const TriangleMesh& mesh, CollisionScene::Data* d);
/// Fills d->node_cones from the triangles' normals (after node_boxes).
void buildNormalCones(CollisionScene::Data* d);
/// Link query through Bullet's BVH (the baseline): GJK/EPA on every triangle in the shape's
/// padded bounding box. `exact` computes EPA depths and fills `hits`.
double queryLinkBullet(const CollisionScene::Data& d, const std::vector<ShapeEntry>& entries,
                       const Eigen::Isometry3d& t, double threshold, bool exact,
                       std::vector<TriangleHit>* hits);
/// One shape (at pose `ts`, object frame) of queryLinkBullet: its minimum distance.
double queryShapeBullet(const CollisionScene::Data& d, const ShapeEntry& e,
                        const Eigen::Isometry3d& ts, double threshold, bool exact,
                        std::vector<TriangleHit>* hits);
/// Same result bit for bit: Bullet's tree walked in its order with the shape's planes as node and
/// triangle test, GJK only where the baseline's result depends on it. With `sat_depths`, shapes
/// with ShapeEntry::sat_depths take their exact hits from boxTrianglePenetration instead (not bit
/// for bit: see GraspSimDiagnostics::separating_axis_contacts).
/// With `seen` (a link of one box): what its overlap walk saw (SeenTriangles).
double queryLinkCulled(const CollisionScene::Data& d, const std::vector<ShapeEntry>& entries,
                       const Eigen::Isometry3d& t, double threshold, bool exact,
                       std::vector<TriangleHit>* hits, bool sat_depths = false,
                       SeenTriangles* seen = nullptr);

/// Smallest signed distance over the exact hits of the link (queryLinkBullet with `exact`)
/// that pass `filter` (all when null); +inf when none; with `hit`, the first such hit in
/// queryLinkBullet's order (lean_query.cpp).
double queryLinkNearest(const CollisionScene::Data& d, const std::vector<ShapeEntry>& entries,
                        const Eigen::Isometry3d& t, double threshold, const FacingFilter* filter,
                        TriangleHit* hit);
/// queryLinkNearest of a link of one box from what its overlap walk at the same pose and
/// threshold saw (`seen` complete): the same answer (lean_query.cpp).
double queryLinkNearestSeen(const CollisionScene::Data& d, const ShapeEntry& e,
                            const Eigen::Isometry3d& ts, double threshold,
                            const FacingFilter* filter, TriangleHit* hit,
                            const SeenTriangles& seen);
/// True when some triangle within `threshold` of a shape of the link at pose `t` is penetrated
/// deeper than `depth` with a separation direction within acos(min_agreement) of its face
/// normal: the same answer as scanning queryLinkBullet's exact hits (lean_query.cpp).
bool queryLinkDeeper(const CollisionScene::Data& d, const std::vector<ShapeEntry>& entries,
                     const Eigen::Isometry3d& t, double threshold, double depth,
                     double min_agreement);

}  // namespace taskmap
