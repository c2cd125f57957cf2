// Primitive distances against an independent convex-QP oracle (projected gradient on the
// parameters of both cores) and, for capsules, FCL when available.
#include "taskmap/reaching/primitive_distance.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <random>

#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

/// Oracle: min over x in [-1,1]^4 of |core_a(x0, x1) - core_b(x2, x3)|, a convex QP, by
/// accelerated projected gradient from many starts.
double oracleCoreDistance(const Primitive& a, const Eigen::Isometry3d& ta, const Primitive& b,
                          const Eigen::Isometry3d& tb) {
  Eigen::Matrix<double, 3, 4> m;  // d(x) = c + M x
  const double hva = a.type == PrimitiveType::kSweptRectangle ? a.half_v : 0.0;
  const double hvb = b.type == PrimitiveType::kSweptRectangle ? b.half_v : 0.0;
  m.col(0) = ta.linear() * a.axes.col(0) * a.half_u;
  m.col(1) = ta.linear() * a.axes.col(1) * hva;
  m.col(2) = -tb.linear() * b.axes.col(0) * b.half_u;
  m.col(3) = -tb.linear() * b.axes.col(1) * hvb;
  const Eigen::Vector3d c = ta * a.center - tb * b.center;
  const double lip = std::max(1e-12, (m.transpose() * m).eigenvalues().real().maxCoeff());
  double best = std::numeric_limits<double>::infinity();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int start = 0; start < 4; ++start) {
    Eigen::Vector4d x(u(rng), u(rng), u(rng), u(rng)), y = x, prev = x;
    for (int it = 0; it < 20000; ++it) {
      const Eigen::Vector4d g = m.transpose() * (c + m * y);
      prev = x;
      x = (y - g / lip).cwiseMax(-1.0).cwiseMin(1.0);
      y = x + (static_cast<double>(it) / (it + 3)) * (x - prev);
    }
    best = std::min(best, (c + m * x).norm());
  }
  return best;
}

Eigen::Isometry3d randomPose(std::mt19937& rng, double spread) {
  std::normal_distribution<double> n(0, 1);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
  t.translation() = spread * Eigen::Vector3d(n(rng), n(rng), n(rng));
  return t;
}

Primitive randomPrimitive(std::mt19937& rng, bool rect) {
  std::uniform_real_distribution<double> u(0.0, 0.2);
  std::normal_distribution<double> n(0, 1);
  if (!rect)
    return Primitive::capsule(Eigen::Vector3d(n(rng), n(rng), n(rng)) * 0.1,
                              Eigen::Vector3d(n(rng), n(rng), n(rng)) * 0.1, u(rng) * 0.3);
  const Eigen::Matrix3d axes =
      Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
  return Primitive::sweptRectangle(Eigen::Vector3d(n(rng), n(rng), n(rng)) * 0.05, axes, u(rng),
                                   u(rng), u(rng) * 0.3);
}

void checkAgainstOracle(bool rect_a, bool rect_b, unsigned seed) {
  std::mt19937 rng(seed);
  int touching = 0;
  for (int i = 0; i < 200; ++i) {
    const Primitive a = randomPrimitive(rng, rect_a), b = randomPrimitive(rng, rect_b);
    const Eigen::Isometry3d ta = randomPose(rng, 0.15), tb = randomPose(rng, 0.15);
    const PrimitiveDistance d = primitiveDistance(a, ta, b, tb);
    const double oracle = oracleCoreDistance(a, ta, b, tb);
    ASSERT_NEAR(d.core_distance, oracle, 1e-7) << "case " << i;
    EXPECT_NEAR(d.distance, d.core_distance - a.radius - b.radius, 1e-15);
    EXPECT_NEAR((d.core_b - d.core_a).norm(), d.core_distance, 1e-12);
    EXPECT_NEAR(d.normal.norm(), 1.0, 1e-12);
    EXPECT_NEAR((d.point_b - d.point_a).dot(d.normal), d.distance, 1e-12);
    if (d.cores_touch) ++touching;
  }
  // The random cases cover both separated and intersecting cores.
  if (rect_a || rect_b) {
    EXPECT_GT(touching, 0);  // two random segments never meet
  }
  EXPECT_LT(touching, 200);
}

TEST(PrimitiveDistance, CapsuleCapsuleMatchesOracle) {
  checkAgainstOracle(false, false, 1);
}
TEST(PrimitiveDistance, CapsuleRectangleMatchesOracle) {
  checkAgainstOracle(false, true, 2);
  checkAgainstOracle(true, false, 3);
}
TEST(PrimitiveDistance, RectangleRectangleMatchesOracle) {
  checkAgainstOracle(true, true, 4);
}

TEST(PrimitiveDistance, ParallelAndDegenerateCases) {
  const Eigen::Isometry3d id = Eigen::Isometry3d::Identity();
  // Parallel overlapping segments 0.3 apart.
  const Primitive a = Primitive::capsule({0, 0, 0}, {1, 0, 0}, 0.1);
  const Primitive b = Primitive::capsule({0.5, 0.3, 0}, {1.5, 0.3, 0}, 0.05);
  EXPECT_NEAR(primitiveDistance(a, id, b, id).distance, 0.15, 1e-15);
  // Spheres (zero-length capsules).
  const Primitive s1 = Primitive::capsule({0, 0, 0}, {0, 0, 0}, 0.1);
  const Primitive s2 = Primitive::capsule({0, 0, 1}, {0, 0, 1}, 0.2);
  const PrimitiveDistance ss = primitiveDistance(s1, id, s2, id);
  EXPECT_NEAR(ss.distance, 0.7, 1e-15);
  EXPECT_NEAR(ss.normal.z(), 1.0, 1e-15);
  // A capsule piercing a table-top rectangle: cores touch, the normal falls back to the
  // centre direction, the distance is minus the radii.
  const Primitive table = Primitive::fromBox(id, {1.0, 1.0, 0.04});
  const Primitive pole = Primitive::capsule({0.1, 0.1, -0.2}, {0.1, 0.1, 0.3}, 0.03);
  const PrimitiveDistance pt = primitiveDistance(pole, id, table, id);
  EXPECT_TRUE(pt.cores_touch);
  EXPECT_NEAR(pt.distance, -0.05, 1e-15);
  EXPECT_TRUE(pt.normal.allFinite());
  // Box as inscribed swept rectangle: exact on the faces.
  const Primitive above = Primitive::capsule({0.2, -0.1, 0.5}, {-0.2, 0.1, 0.5}, 0.1);
  EXPECT_NEAR(primitiveDistance(above, id, table, id).distance, 0.5 - 0.02 - 0.1, 1e-15);
}

}  // namespace
}  // namespace taskmap
