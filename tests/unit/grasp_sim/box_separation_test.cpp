// The box-triangle separating-axis gap with a limit (grasp_sim/src/triangle_query.cpp) against
// the same gap without one: the same value at or below the limit, a value above it otherwise.
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "collision_data.hpp"

namespace taskmap {
namespace {

TEST(BoxSeparation, LimitOnlyShortensTheSearch) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d c(0.001, -0.002, 0.003), e(0.01, 0.02, 0.005);
  const double inf = std::numeric_limits<double>::infinity();
  int below = 0, above = 0;
  for (int k = 0; k < 20000; ++k) {
    btVector3 tri[3];
    for (auto& p : tri) p = btVector3(u(rng), u(rng), u(rng));
    const double full = boxTriangleSeparation(c, r, e, tri);
    for (double limit : {-0.01, 0.0, 5e-4, 0.01, full, inf}) {
      const double cut = boxTriangleSeparation(c, r, e, tri, limit);
      if (full <= limit) {
        ASSERT_EQ(cut, full) << "limit " << limit;
        ++below;
      } else {
        ASSERT_GT(cut, limit) << "full " << full;
        ASSERT_LE(cut, full);
        ++above;
      }
    }
  }
  EXPECT_GT(below, 1000);
  EXPECT_GT(above, 1000);
}

}  // namespace
}  // namespace taskmap
