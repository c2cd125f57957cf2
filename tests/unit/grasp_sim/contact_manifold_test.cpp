#include "taskmap/grasp_sim/contact_manifold.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <gtest/gtest.h>

#include "taskmap/core/random.hpp"
#include "taskmap/grasp_sim/grasp_simulator.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {
namespace {

Contact at(double x, double y, double depth) {
  Contact c;
  c.point = Eigen::Vector3d(x, y, 0.0);
  c.normal = Eigen::Vector3d::UnitZ();
  c.depth = depth;
  c.link = 2;
  return c;
}

TEST(ContactManifoldTest, SmallSetsAndZeroLimitAreUnchanged) {
  const std::vector<Contact> cs = {at(0, 0, 2e-3), at(0.01, 0, 1e-3), at(0, 0.01, 5e-4)};
  EXPECT_EQ(contactManifold(cs, 4).size(), 3u);
  EXPECT_EQ(contactManifold(cs, 0).size(), 3u);
}

TEST(ContactManifoldTest, KeepsDeepestAndSpansThePatch) {
  // 5 x 5 grid, deepest at the centre; depths fall off with the distance to it.
  std::vector<Contact> cs;
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j)
      cs.push_back(at(0.01 * i, 0.01 * j, 2e-3 - 1e-4 * (i * i + j * j)));
  std::stable_sort(cs.begin(), cs.end(),
                   [](const Contact& a, const Contact& b) { return a.depth > b.depth; });
  const auto m = contactManifold(cs, 4);
  ASSERT_EQ(m.size(), 4u);
  EXPECT_EQ(m[0].point, Eigen::Vector3d::Zero());  // the deepest stays, first
  // Brute force: the second pick is at the largest distance from the deepest (a grid corner).
  double far = 0.0;
  for (const auto& c : cs) far = std::max(far, c.point.norm());
  bool has_corner = false;
  for (const auto& c : m) has_corner |= std::abs(c.point.norm() - far) < 1e-12;
  EXPECT_TRUE(has_corner);
  // The picks span the patch: the chosen points are not collinear.
  const Eigen::Vector3d a = m[1].point - m[0].point, b = m[2].point - m[0].point,
                        c = m[3].point - m[0].point;
  EXPECT_GT(std::max(a.cross(b).norm(), a.cross(c).norm()), 1e-4);
}

TEST(ContactManifoldTest, SimulatorKeepsAtMostFourContactsPerLink) {
  const ObjectModel sphere = ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/sphere.obj");
  const HandModel hand =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf");
  GraspSimOptions unlimited;
  unlimited.max_contacts_per_link = 0;
  const GraspSimulator sim(sphere, hand);
  const GraspSimulator sim_all(sphere, hand, unlimited);
  int compared = 0, reduced = 0;
  for (std::uint64_t t = 0; t < 40 && compared < 5; ++t) {
    Rng rng(7, t);
    const Pose start{sphere.sampleInside(rng), rng.rotation()};
    const GraspResult r = sim.simulate(start);
    const GraspResult all = sim_all.simulate(start);
    if (r.status != GraspStatus::kOk) continue;
    ++compared;
    std::map<int, int> per_link, per_link_all;
    for (const auto& c : r.contacts) per_link[c.link]++;
    for (const auto& c : all.contacts) per_link_all[c.link]++;
    for (const auto& kv : per_link) EXPECT_LE(kv.second, 4);
    // Same links touch; the manifold is a subset of the unlimited contacts.
    EXPECT_EQ(per_link.size(), per_link_all.size());
    for (const auto& c : r.contacts) {
      bool found = false;
      for (const auto& d : all.contacts) found |= (c.point == d.point && c.link == d.link);
      EXPECT_TRUE(found);
    }
    reduced += all.contacts.size() > r.contacts.size();
  }
  EXPECT_GE(compared, 3);
  EXPECT_GE(reduced, 1);  // the sphere's fine tessellation gives more than 4 per link somewhere
}

}  // namespace
}  // namespace taskmap
