// ClosingChecker::Model: the Bullet shapes, link masses and joint layout shared by every check.
#include "closing_model.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <Eigen/Eigenvalues>

#include "collision_data.hpp"
#include "taskmap/core/constants.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/hands/link_inertia.hpp"
#include "taskmap/meshes/convex_pieces.hpp"

namespace taskmap {
namespace {

/// Bullet's convex hull, with access to its cached bounding box (protected in Bullet).
class BoxedHull : public btConvexHullShape {
 public:
  using btConvexHullShape::btConvexHullShape;
  /// Grows the cached bounding box by `pad` (m) on every side.
  void pad(double pad) {
    btVector3 lo, hi;
    getCachedLocalAabb(lo, hi);
    const btVector3 d(pad, pad, pad);
    setCachedLocalAabb(lo - d, hi + d);
  }
};

}  // namespace

std::unique_ptr<btConvexHullShape> hullShape(const std::vector<Eigen::Vector3d>& points,
                                             double margin, double pad) {
  auto hull = std::make_unique<BoxedHull>(points.front().data(), static_cast<int>(points.size()),
                                          sizeof(Eigen::Vector3d));
  hull->optimizeConvexHull();
  hull->setMargin(margin);
  // The constructor cached the bounding box with Bullet's default margin (4 cm) and setMargin
  // keeps it: recomputed, it is the hull's grown by `margin` (getAabb adds `margin` again).
  hull->recalcLocalAabb();
  hull->pad(pad);
  return hull;
}

double staleDisc(const btCompoundShape& tight,
                 const std::vector<const std::vector<Eigen::Vector3d>*>& hulls, double margin) {
  btCompoundShape stale(false, tight.getNumChildShapes());
  std::vector<std::unique_ptr<btConvexHullShape>> own;
  for (int i = 0; i < tight.getNumChildShapes(); ++i) {
    const std::vector<Eigen::Vector3d>* points = hulls[static_cast<std::size_t>(i)];
    if (!points) {
      stale.addChildShape(tight.getChildTransform(i),
                          const_cast<btCollisionShape*>(tight.getChildShape(i)));
      continue;
    }
    own.push_back(std::make_unique<btConvexHullShape>(
        points->front().data(), static_cast<int>(points->size()), sizeof(Eigen::Vector3d)));
    own.back()->optimizeConvexHull();
    own.back()->setMargin(margin);  // the box cached by the constructor stays
    stale.addChildShape(tight.getChildTransform(i), own.back().get());
  }
  return stale.getAngularMotionDisc();
}

namespace {

std::unique_ptr<btConvexShape> convexShape(const CollisionShape& s, double margin) {
  std::unique_ptr<btConvexShape> shape;
  switch (s.type) {
    case ShapeType::kBox:
      shape = std::make_unique<btBoxShape>(bt(Eigen::Vector3d(0.5 * s.box_size)));
      break;
    case ShapeType::kCylinder:
      shape = std::make_unique<btCylinderShapeZ>(btVector3(s.radius, s.radius, 0.5 * s.length));
      break;
    case ShapeType::kSphere:
      return std::make_unique<btSphereShape>(s.radius);  // its margin is its radius
    case ShapeType::kConvex:
      return hullShape(s.points, margin, 0.0);
  }
  shape->setMargin(margin);
  return shape;
}

}  // namespace

ClosingLink ClosingChecker::Model::makeLink(int link, int parent, int joint) {
  ClosingLink c;
  c.link = link;
  c.parent = parent;
  c.joint = joint;
  const HandLink& l = hand.links()[static_cast<std::size_t>(link)];
  // The hold test's mass and sphere inertia about the shapes' centre, moved to the link origin
  // (the multibody link's centre of mass) by the parallel-axis term.
  const LinkInertia m = linkInertia(l, options.link_density);
  c.mass = m.mass;
  c.inertia = m.inertia + m.mass * m.centre.squaredNorm();
  if (l.shapes.empty()) return c;
  c.shape = std::make_unique<ClosingCompound>(static_cast<int>(l.shapes.size()));
  std::vector<const std::vector<Eigen::Vector3d>*> hulls;
  for (const auto& s : l.shapes) {
    convex.push_back(convexShape(s, options.margin));
    c.shape->addChildShape(bt(s.origin), convex.back().get());
    hulls.push_back(s.type == ShapeType::kConvex ? &s.points : nullptr);
  }
  c.shape->disc = staleDisc(*c.shape, hulls, options.margin);
  return c;
}

void ClosingChecker::Model::makeObject(const ObjectModel& o) {
  const MassProperties& mp = o.massProperties();
  // Principal axes of the inertia (per unit density) scaled to the check's mass.
  const Eigen::Matrix3d inertia = (options.object_mass / mp.volume) * mp.inertia;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
  Eigen::Matrix3d axes = eig.eigenvectors();
  if (axes.determinant() < 0.0) axes.col(2) = -axes.col(2);
  object_inertia = eig.eigenvalues().cwiseMax(1e-12);
  object_principal = Eigen::Isometry3d::Identity();
  object_principal.linear() = axes;
  object_principal.translation() = mp.center_of_mass;
  ConvexPiecesOptions po;
  po.max_pieces = options.object_max_pieces;
  const ConvexPieces pieces = convexPieces(o.mesh(), po, "object '" + o.name() + "'");
  object_pieces = static_cast<int>(pieces.pieces.size());
  object = std::make_unique<ClosingCompound>(object_pieces);
  const Eigen::Isometry3d to_principal = object_principal.inverse();
  std::vector<std::vector<Eigen::Vector3d>> local(pieces.pieces.size());
  btCompoundShape tight(false, object_pieces);  // the pieces unpadded: the object's disc
  std::vector<std::unique_ptr<btConvexHullShape>> unpadded;
  for (std::size_t i = 0; i < pieces.pieces.size(); ++i) {
    for (const auto& p : pieces.pieces[i]) local[i].push_back(to_principal * p);
    unpadded.push_back(hullShape(local[i], options.margin, 0.0));
    tight.addChildShape(btTransform::getIdentity(), unpadded.back().get());
  }
  std::vector<const std::vector<Eigen::Vector3d>*> hulls;
  for (const auto& l : local) hulls.push_back(&l);
  object->disc = staleDisc(tight, hulls, options.margin);
  // A hand-object manifold keeps contacts within gContactBreakingThreshold times the smaller
  // disc of the two bodies (btCollisionDispatcher::getNewManifold): padding the pieces' boxes by
  // that much lets every pair in contact distance reach the narrow phase.
  double links_disc = base.shape ? base.shape->disc : 0.0;
  for (const ClosingLink& l : links)
    if (l.shape) links_disc = std::max(links_disc, l.shape->disc);
  const double pad = static_cast<double>(gContactBreakingThreshold) *
                     std::min(static_cast<double>(object->disc), links_disc);
  for (const auto& l : local) {
    std::unique_ptr<btConvexHullShape> hull = hullShape(l, options.margin, pad);
    object->addChildShape(btTransform::getIdentity(), hull.get());
    convex.push_back(std::move(hull));
  }
}

ClosingChecker::Model::Model(const ObjectModel& o, const HandModel& h,
                             const ClosingCheckOptions& opt)
    : hand(h), options(opt) {
  options.validate();
  const auto& hl = hand.links();
  const auto& hj = hand.joints();
  std::vector<std::vector<int>> children(hl.size());
  int root = -1;
  for (std::size_t j = 0; j < hj.size(); ++j)
    children[static_cast<std::size_t>(hj[j].parent_link)].push_back(static_cast<int>(j));
  for (std::size_t l = 0; l < hl.size(); ++l)
    if (hl[l].parent_joint < 0) root = static_cast<int>(l);
  if (root < 0) throw Error("closing check: hand '" + hand.name() + "' has no root link");
  multibody_of.assign(hl.size(), -2);
  base = makeLink(root, -1, -1);
  multibody_of[static_cast<std::size_t>(root)] = -1;
  // Breadth first from the root: a multibody link's parent comes before it.
  std::vector<int> queue{root};
  for (std::size_t next = 0; next < queue.size(); ++next) {
    const int l = queue[next];
    for (int j : children[static_cast<std::size_t>(l)]) {
      const int child = hj[static_cast<std::size_t>(j)].child_link;
      multibody_of[static_cast<std::size_t>(child)] = static_cast<int>(links.size());
      links.push_back(makeLink(child, multibody_of[static_cast<std::size_t>(l)], j));
      queue.push_back(child);
    }
  }
  const DriveOptions drive{options.kp_revolute, options.kp_prismatic, options.jaw_force,
                           options.revolute_gripper_force};
  drives = jointDrives(hand, drive);
  // Parallel grippers: driven prismatic jaws, or one revolute joint pressing with jaw_force.
  jaws = revoluteGripper(hand, drive).lever > 0.0;
  for (const HandJoint& j : hj)
    if (j.type == JointType::kPrismatic && j.driver >= 0) jaws = true;
  makeObject(o);
}

}  // namespace taskmap
