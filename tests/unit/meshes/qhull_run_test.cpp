// runQhull, the one qhull set-up shared by hand collision hulls and quality's wrench hulls:
// a cube and a 4-D cross-polytope against their known facets and volumes, flat input, bad calls.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "taskmap/core/error.hpp"
#include "taskmap/meshes/qhull_run.hpp"

namespace taskmap {
namespace {

TEST(QhullRun, CubeWithAnInnerPoint) {
  std::vector<double> c;
  for (int i = 0; i < 8; ++i)
    c.insert(c.end(), {double(i & 1), double(i >> 1 & 1), double(i >> 2)});
  c.insert(c.end(), {0.5, 0.5, 0.5});  // inside: not a hull vertex
  const QhullOutput q = runQhull(3, c, "Qt FA", true, true);
  ASSERT_EQ(q.exit_code, 0) << q.error;
  EXPECT_NEAR(q.volume, 1.0, 1e-12);
  std::vector<int> v = q.vertices;
  std::sort(v.begin(), v.end());
  EXPECT_EQ(v, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  ASSERT_EQ(q.normals.cols(), 12);  // two triangles per square face ("Qt")
  for (Eigen::Index f = 0; f < q.normals.cols(); ++f) {
    EXPECT_NEAR(q.normals.col(f).norm(), 1.0, 1e-12);
    EXPECT_NEAR(q.normals.col(f).cwiseAbs().maxCoeff(), 1.0, 1e-12);  // axis-aligned
    // Every corner on or below the facet plane n.x + offset = 0.
    for (int i = 0; i < 8; ++i)
      EXPECT_LE(q.normals.col(f).dot(Eigen::Vector3d(c[3 * i], c[3 * i + 1], c[3 * i + 2])) +
                    q.offsets(f),
                1e-12);
  }
}

TEST(QhullRun, CrossPolytopeIn4D) {
  std::vector<double> c;
  for (int k = 0; k < 4; ++k)
    for (const double s : {1.0, -1.0}) {
      std::vector<double> p(4, 0.0);
      p[static_cast<std::size_t>(k)] = s;
      c.insert(c.end(), p.begin(), p.end());
    }
  const QhullOutput q = runQhull(4, c, "FA", true, false);
  ASSERT_EQ(q.exit_code, 0) << q.error;
  EXPECT_EQ(q.normals.cols(), 16);                                               // 2^4 facets
  EXPECT_NEAR(q.volume, 16.0 / 24.0, 1e-12);                                     // 2^n / n!
  for (Eigen::Index f = 0; f < 16; ++f) EXPECT_NEAR(q.offsets(f), -0.5, 1e-12);  // 1/sqrt(4)
  EXPECT_TRUE(q.vertices.empty());                                               // not asked for
}

TEST(QhullRun, FlatInputIsSingularAndBadCallsThrow) {
  const std::vector<double> flat = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  const QhullOutput q = runQhull(3, flat, "Qt FA", true, true);
  EXPECT_NE(q.exit_code, 0);
  EXPECT_TRUE(q.singular);
  EXPECT_EQ(q.error, "singular input (initial simplex is flat)");
  EXPECT_THROW(runQhull(3, {0, 0, 0, 1}, "FA", true, true), Error);
  EXPECT_THROW(runQhull(1, {0, 1}, "FA", true, true), Error);
}

}  // namespace
}  // namespace taskmap
