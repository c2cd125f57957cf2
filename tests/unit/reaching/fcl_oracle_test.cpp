// Capsule-capsule and capsule-box distances against FCL (test-only oracle, libfcl-dev).
#include <gtest/gtest.h>

#include <fcl/narrowphase/distance.h>

#include <random>

#include "taskmap/reaching/primitive_distance.hpp"

namespace taskmap {
namespace {

/// FCL pose of a capsule primitive: FCL capsules lie along their frame's z axis.
fcl::Transform3d fclPose(const Primitive& p, const Eigen::Isometry3d& body) {
  fcl::Transform3d t = fcl::Transform3d::Identity();
  Eigen::Matrix3d r;
  r.col(2) = p.axes.col(0);
  r.col(0) = p.axes.col(1);
  r.col(1) = r.col(2).cross(r.col(0));
  t.linear() = body.linear() * r;
  t.translation() = body * p.center;
  return t;
}

double fclDistance(const std::shared_ptr<fcl::CollisionGeometryd>& ga, const fcl::Transform3d& ta,
                   const std::shared_ptr<fcl::CollisionGeometryd>& gb, const fcl::Transform3d& tb) {
  fcl::CollisionObjectd oa(ga, ta), ob(gb, tb);
  fcl::DistanceRequestd request;
  request.gjk_solver_type = fcl::GST_INDEP;
  request.distance_tolerance = 1e-10;
  fcl::DistanceResultd result;
  fcl::distance(&oa, &ob, request, result);
  return result.min_distance;
}

TEST(FclOracle, CapsuleDistancesMatchFcl) {
  std::mt19937 rng(21);
  std::normal_distribution<double> n(0, 1);
  std::uniform_real_distribution<double> u(0.01, 0.08);
  int compared = 0;
  for (int i = 0; i < 500; ++i) {
    const Primitive a = Primitive::capsule(0.2 * Eigen::Vector3d(n(rng), n(rng), n(rng)),
                                           0.2 * Eigen::Vector3d(n(rng), n(rng), n(rng)), u(rng));
    const Primitive b = Primitive::capsule(0.2 * Eigen::Vector3d(n(rng), n(rng), n(rng)),
                                           0.2 * Eigen::Vector3d(n(rng), n(rng), n(rng)), u(rng));
    const Eigen::Isometry3d id = Eigen::Isometry3d::Identity();
    const PrimitiveDistance d = primitiveDistance(a, id, b, id);
    if (d.distance < 1e-3) continue;  // FCL reports overlaps differently
    const auto ga = std::make_shared<fcl::Capsuled>(a.radius, 2 * a.half_u);
    const auto gb = std::make_shared<fcl::Capsuled>(b.radius, 2 * b.half_u);
    EXPECT_NEAR(d.distance, fclDistance(ga, fclPose(a, id), gb, fclPose(b, id)), 1e-6) << i;
    ++compared;
  }
  EXPECT_GT(compared, 300);
}

TEST(FclOracle, CapsuleToTableBoxMatchesFclAwayFromEdges) {
  // The table top as a box; capsules above its face (where the inscribed swept rectangle is
  // exact) must have FCL's box distance.
  const Eigen::Vector3d size(1.0, 0.8, 0.04);
  const Eigen::Isometry3d id = Eigen::Isometry3d::Identity();
  const Primitive table = Primitive::fromBox(id, size);
  const auto box = std::make_shared<fcl::Boxd>(size.x(), size.y(), size.z());
  std::mt19937 rng(22);
  std::uniform_real_distribution<double> xy(-0.3, 0.3), z(0.08, 0.4), r(0.01, 0.05);
  for (int i = 0; i < 200; ++i) {
    const Primitive c =
        Primitive::capsule({xy(rng), xy(rng), z(rng)}, {xy(rng), xy(rng), z(rng)}, r(rng));
    const PrimitiveDistance d = primitiveDistance(c, id, table, id);
    const auto cap = std::make_shared<fcl::Capsuled>(c.radius, 2 * c.half_u);
    EXPECT_NEAR(d.distance, fclDistance(cap, fclPose(c, id), box, fcl::Transform3d::Identity()),
                1e-6)
        << i;
  }
}

}  // namespace
}  // namespace taskmap
