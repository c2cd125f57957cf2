#pragma once
// Private to grasp_sim: what every closing check of one hand and object shares (Bullet shapes,
// link masses, the multibody's joint layout), built once and read by all threads.

#include <memory>
#include <vector>

#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btConvexShape.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/grasp_sim/closing_check.hpp"
#include "taskmap/hands/hand_drive.hpp"
#include "taskmap/hands/hand_model.hpp"

namespace taskmap {

struct ClosingWorld;  // one check's Bullet world (closing_world.cpp)

/// A Bullet convex hull of `points` (at least 4, not flat; m) with collision margin `margin`
/// whose cached bounding box is the hull's grown by margin + pad (Bullet's constructor caches it
/// with its default 4 cm margin, which setMargin does not recompute; docs/METHOD.md §4d).
std::unique_ptr<btConvexHullShape> hullShape(const std::vector<Eigen::Vector3d>& points,
                                             double margin, double pad);

/// A compound whose contact breaking threshold (how far apart Bullet keeps a contact point of
/// its manifolds, and finds one) is factor x `disc`, set by the model: the disc Bullet gave it
/// while the hull boxes carried the stale 4 cm margin, so the check's contacts are unchanged.
class ClosingCompound : public btCompoundShape {
 public:
  /// Room for n children, with Bullet's dynamic box tree.
  explicit ClosingCompound(int n) : btCompoundShape(true, n) {}
  double disc = 0.0;  ///< m, the angular motion disc the threshold uses
  /// factor x disc, m.
  btScalar getContactBreakingThreshold(btScalar factor) const override {
    return factor * static_cast<btScalar>(disc);
  }
};

/// The angular motion disc (m) Bullet computed for `tight` when its hull children (those with
/// points in `hulls`, one entry per child, null for the others) kept the box their constructor
/// cached with the 4 cm default margin; `margin` (m) is the hulls' collision margin.
double staleDisc(const btCompoundShape& tight,
                 const std::vector<const std::vector<Eigen::Vector3d>*>& hulls, double margin);

/// One hand link as a multibody link (its centre of mass at the link frame's origin).
struct ClosingLink {
  int link = -1;    ///< index into HandModel::links()
  int parent = -1;  ///< multibody index of the parent link, -1 for the base (root link)
  int joint = -1;   ///< index into HandModel::joints() of the joint from the parent
  double mass = 0.0;
  double inertia = 0.0;                    ///< kg m^2, about each axis through the link origin
  std::unique_ptr<ClosingCompound> shape;  ///< null for links without collision shapes
};

struct ClosingChecker::Model {
  HandModel hand;
  ClosingCheckOptions options;
  ClosingLink base;                                    ///< the root link (fixed)
  std::vector<ClosingLink> links;                      ///< the others, parents first
  std::vector<std::unique_ptr<btConvexShape>> convex;  ///< every convex child shape (owned)
  std::unique_ptr<ClosingCompound> object;             ///< pieces in the principal frame
  Eigen::Isometry3d object_principal;                  ///< principal frame in the object frame
  Eigen::Vector3d object_inertia = Eigen::Vector3d::Zero();  ///< principal moments, kg m^2
  int object_pieces = 0;
  /// A parallel gripper (a driven prismatic joint, or a revolute gripper pressing with
  /// jaw_force): ClosingCheckOptions::jaws apply
  bool jaws = false;
  std::vector<int> multibody_of;   ///< per hand link: multibody index (-1 base, -2 none)
  std::vector<JointDrive> drives;  ///< per URDF joint: its motor's gain and force limit

  Model(const ObjectModel& object, const HandModel& h, const ClosingCheckOptions& o);
  /// Runs one check (closing_world.cpp).
  ClosingCheckResult run(const Pose& palm, const Eigen::VectorXd& joints) const;
  /// kPushes: the six pushes after the closing, the hand holding `squeeze` (closing_world.cpp).
  void push(const Eigen::VectorXd& squeeze, double h, ClosingWorld* w, ClosingCheckResult* r) const;

 private:
  ClosingLink makeLink(int link, int parent, int joint);
  void makeObject(const ObjectModel& object);
};

}  // namespace taskmap
