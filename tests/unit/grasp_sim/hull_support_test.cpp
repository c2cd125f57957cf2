// Hull support cells (grasp_sim/src/hull_support.hpp) against Bullet's scan of every point:
// the same support point (ties to the first index included) on real and synthetic hulls.
#include "hull_support.hpp"

#include <cmath>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "taskmap/hands/hand_model.hpp"

namespace taskmap {
namespace {

/// Random directions, axis and diagonal directions (exact ties on boxes), tiny and huge
/// scales, directions on cube-map cell borders, zero.
std::vector<Eigen::Vector3d> directions(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d v(g(rng), g(rng), g(rng));
    out.push_back(v);
    out.push_back(1e-9 * v);
    out.push_back(1e6 * v);
  }
  const int k = HullSupportCells::kCellsPerEdge;
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b)
      for (int c = -1; c <= 1; ++c) out.emplace_back(a, b, c);
  for (int i = 0; i <= k; ++i)
    for (int j = 0; j <= k; ++j) {
      const double u = -1.0 + 2.0 * i / k, w = -1.0 + 2.0 * j / k;
      out.emplace_back(1.0, u, w);
      out.emplace_back(-u, -1.0, w);
      out.emplace_back(u, std::nextafter(w, 2.0), 1.0);
    }
  return out;
}

void expectSame(const std::vector<Eigen::Vector3d>& points, unsigned seed) {
  const HullSupportCheck check(points);
  int n = 0;
  for (const auto& d : directions(3000, seed)) {
    const Eigen::Vector3d a = check.scan(d), b = check.indexed(d);
    ASSERT_TRUE(a == b) << "direction " << d.transpose() << ": scan " << a.transpose() << ", cells "
                        << b.transpose();
    ASSERT_TRUE(check.scanVirtual(d) == check.indexedVirtual(d)) << d.transpose();
    ++n;
  }
  EXPECT_GT(n, 9000);
}

TEST(HullSupport, SameAsBulletScanOnRandomHull) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0.0, 0.03);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 400; ++i) pts.emplace_back(g(rng), 0.5 * g(rng), 2.0 * g(rng));
  expectSame(pts, 1);
}

TEST(HullSupport, SameAsBulletScanWithExactTies) {
  // A box with extra points on its faces and edges: many directions have several maxima.
  std::vector<Eigen::Vector3d> pts;
  for (int x = -2; x <= 2; ++x)
    for (int y = -2; y <= 2; ++y)
      for (int z = -2; z <= 2; ++z)
        if (std::abs(x) == 2 || std::abs(y) == 2 || std::abs(z) == 2)
          pts.emplace_back(0.01 * x, 0.02 * y, 0.005 * z);
  expectSame(pts, 2);
}

// Real inputs (tests/data/real, see its README): the Franka hand's mesh palm and jaws.
TEST(HullSupport, SameAsBulletScanOnFrankaHand) {
  const std::string urdf = std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/franka_hand.urdf";
  if (!std::ifstream(urdf)) GTEST_SKIP() << "real inputs not in " << TEST_DATA_DIR << "/real";
  const HandModel hand = HandModel::load(urdf);
  int hulls = 0;
  for (const auto& link : hand.links())
    for (const auto& s : link.shapes)
      if (s.type == ShapeType::kConvex) {
        expectSame(s.points, 10u + static_cast<unsigned>(hulls));
        ++hulls;
      }
  EXPECT_GE(hulls, 1);  // the palm (the jaws are boxes)
}

TEST(HullSupport, CellsKeepFewCandidates) {
  std::mt19937 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 100; ++i) pts.push_back(Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized());
  const HullSupportCells cells(pts);
  EXPECT_EQ(cells.cellCount(), 6u * 256u);
  EXPECT_LT(cells.meanCandidates(), 20.0);  // the point of the cells: far fewer than 100
  EXPECT_EQ(cells.cell(0.0, 0.0, 0.0), nullptr);
  EXPECT_EQ(cells.cell(std::nan(""), 1.0, 0.0), nullptr);
}

}  // namespace
}  // namespace taskmap
