#pragma once
// Private to grasp_sim (Bullet side of hull_support.hpp): a btConvexHullShape whose support
// point comes from HullSupportCells. Its shape type is Bullet's custom convex type so that
// GJK/EPA (btConvexShape::localGetSupportVertexWithoutMarginNonVirtual) call the virtual
// support below instead of scanning every point; everything else is btConvexHullShape's.

#include <BulletCollision/CollisionShapes/btConvexHullShape.h>

#include "hull_support.hpp"

namespace taskmap {

class IndexedHullShape : public btConvexHullShape {
 public:
  /// Same construction as the baseline's hull: the points, optimizeConvexHull, `margin`.
  IndexedHullShape(const std::vector<Eigen::Vector3d>& points, double margin);
  btVector3 localGetSupportingVertexWithoutMargin(const btVector3& vec) const override;
  const char* getName() const override { return "TaskmapIndexedHull"; }

 private:
  std::unique_ptr<HullSupportCells> cells_;
};

}  // namespace taskmap
