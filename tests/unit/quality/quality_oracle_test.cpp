// evaluateGrasp (qhull) against independent oracles on random contact sets:
//  * force closure against a linear program (hull_oracles.hpp: two-phase simplex) and against
//    a brute-force enumeration of supporting hyperplanes over all 6-point subsets;
//  * epsilon against the brute-force enumeration (exact, small sets: 12 wrenches), and, with
//    GraspIt!'s default 8 cone edges, against LP ray shooting along the nearest facet normal,
//    the support function of every facet and a random-direction lower bound.
// Built twice: quality_oracle_test (label unit, small counts, fast under sanitizers) and
// quality_oracle_slow_test (label slow, QUALITY_ORACLE_FULL: 10,000 brute-force sets).
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "hull_oracles.hpp"
#include "quality_fixtures.hpp"
#include "taskmap/quality/grasp_quality.hpp"
#include "taskmap/quality/wrench_hull.hpp"

namespace taskmap {
namespace {

// Distinct suite names keep the two executables' ctest entries (and labels) apart.
#ifdef QUALITY_ORACLE_FULL
constexpr int kBruteForceSets = 10000;
constexpr int kDefaultConeSets = 2000;
#define ORACLE_SUITE QualityOracleSlowTest
#else
constexpr int kBruteForceSets = 150;
constexpr int kDefaultConeSets = 30;
#define ORACLE_SUITE QualityOracleTest
#endif

/// A random grasp with exactly 12 edge wrenches (C(12, 6) = 924 hyperplane candidates).
struct SmallGrasp {
  std::vector<Contact> contacts;
  Eigen::Vector3d com;
  double torque_scale;
  QualityOptions options;
};

SmallGrasp smallGrasp(Rng& rng, int kind) {
  SmallGrasp g;
  g.com =
      Eigen::Vector3d(rng.uniform(-5e-3, 5e-3), rng.uniform(-5e-3, 5e-3), rng.uniform(-5e-3, 5e-3));
  g.torque_scale = rng.uniform(0.03, 0.08);
  g.options.friction = rng.uniform(0.2, 1.2);
  const double tilt = rng.uniform() < 0.5 ? 0.0 : 0.3;
  switch (kind % 3) {
    case 0:  // 3 point contacts x 4 edges
      g.options.cone_edges = 4;
      g.contacts = testing::randomContacts(rng, 3, tilt);
      break;
    case 1:  // 2 soft fingers x (4 edges + 2 torsion edges)
      g.options.cone_edges = 4;
      g.options.contact_model = ContactModel::kSoftFinger;
      g.options.torsional_friction = rng.uniform(0.002, 0.02);
      g.contacts = testing::randomContacts(rng, 2, tilt);
      break;
    default:  // 4 point contacts x 3 edges
      g.options.cone_edges = 3;
      g.contacts = testing::randomContacts(rng, 4, tilt);
      break;
  }
  return g;
}

TEST(ORACLE_SUITE, ForceClosureAndEpsilonAgreeWithBruteForceAndLp) {
  int closures = 0, open = 0, degenerate = 0;
  double worst_rel = 0.0;
  for (int s = 0; s < kBruteForceSets; ++s) {
    Rng rng(2024, static_cast<std::uint64_t>(s));
    const SmallGrasp g = smallGrasp(rng, s);
    const auto w = contactWrenches(g.contacts, g.com, g.torque_scale, g.options);
    ASSERT_EQ(w.cols(), 12);
    const QualityResult r = evaluateGrasp(g.contacts, g.com, g.torque_scale, g.options);
    if (testing::affineRank(w) < 6) {
      EXPECT_EQ(r.status, QualityStatus::kDegenerate) << "set " << s;
      EXPECT_FALSE(r.force_closure);
      ++degenerate;
      continue;
    }
    ASSERT_EQ(r.status, QualityStatus::kOk) << "set " << s << ": " << r.message;
    bool inside = false;
    const double eps = testing::bruteForceEpsilon(w, &inside);
    const double margin = testing::closureMargin(w);
    EXPECT_EQ(r.force_closure, inside) << "set " << s << " brute-force eps " << eps;
    EXPECT_EQ(r.force_closure, margin > 1e-9) << "set " << s << " LP margin " << margin;
    if (inside) {
      EXPECT_NEAR(r.epsilon, eps, 1e-9 * eps) << "set " << s;
      worst_rel = std::max(worst_rel, std::abs(r.epsilon - eps) / eps);
      ++closures;
    } else {
      EXPECT_EQ(r.epsilon, 0.0);
      ++open;
    }
  }
  // Both outcomes must be well represented, or the agreement proves little.
  EXPECT_GT(closures, kBruteForceSets / 10);
  EXPECT_GT(open, kBruteForceSets / 10);
  RecordProperty("closures", closures);
  RecordProperty("open", open);
  RecordProperty("degenerate", degenerate);
  std::printf(
      "brute force: %d force closure, %d not, %d degenerate; worst relative epsilon "
      "difference %.3g\n",
      closures, open, degenerate, worst_rel);
}

TEST(ORACLE_SUITE, DefaultConeAgreesWithLinearPrograms) {
  int closures = 0, open = 0;
  double worst_rel = 0.0;
  for (int s = 0; s < kDefaultConeSets; ++s) {
    Rng rng(4048, static_cast<std::uint64_t>(s));
    const int n = 3 + s % 4;  // 3..6 contacts, 24..48 wrenches
    const auto contacts = testing::randomContacts(rng, n, s % 2 ? 0.3 : 0.0);
    const Eigen::Vector3d com = Eigen::Vector3d::Zero();
    const double r_scale = 0.05;
    const auto w = contactWrenches(contacts, com, r_scale);
    const QualityResult r = evaluateGrasp(contacts, com, r_scale);
    ASSERT_EQ(r.status, QualityStatus::kOk) << "set " << s << ": " << r.message;
    const double margin = testing::closureMargin(w);
    EXPECT_EQ(r.force_closure, margin > 1e-9) << "set " << s << " LP margin " << margin;
    if (!r.force_closure) {
      ++open;
      continue;
    }
    ++closures;
    const WrenchHull hull = wrenchHull(w);
    ASSERT_EQ(hull.status, QualityStatus::kOk);
    // Every facet is a supporting hyperplane: max_i u_f . w_i = -b_f.
    Eigen::Index nearest = 0;
    for (Eigen::Index f = 0; f < hull.offsets.size(); ++f) {
      const double support = (hull.normals.col(f).transpose() * w).maxCoeff();
      EXPECT_NEAR(support, -hull.offsets(f), 1e-10 * hull.scale) << "set " << s << " facet " << f;
      if (hull.offsets(f) > hull.offsets(nearest)) nearest = f;
    }
    // LP ray shooting along the nearest facet normal reaches the boundary at distance epsilon.
    const Eigen::Matrix<double, 6, 1> u = hull.normals.col(nearest);
    const double ray = testing::rayDistance(w, u);
    EXPECT_NEAR(ray, r.epsilon, 1e-9 * r.epsilon) << "set " << s;
    worst_rel = std::max(worst_rel, std::abs(ray - r.epsilon) / r.epsilon);
    // Lower bound: the support function in random directions is never below epsilon.
    for (int k = 0; k < 50; ++k) {
      Eigen::Matrix<double, 6, 1> d;
      for (int i = 0; i < 6; ++i) d(i) = rng.normal();
      d.normalize();
      EXPECT_GE((d.transpose() * w).maxCoeff(), r.epsilon * (1.0 - 1e-12));
    }
  }
  EXPECT_GT(closures, kDefaultConeSets / 10);
  EXPECT_GT(open, kDefaultConeSets / 10);
  std::printf(
      "default cone: %d force closure, %d not; worst relative ray/epsilon difference "
      "%.3g\n",
      closures, open, worst_rel);
}

}  // namespace
}  // namespace taskmap
