// Unit tests of taskmap::wrenchEpsilon (incremental hull, Zheng's refinement) against qhull
// (wrenchHull) and analytic cases. The incremental path runs with allow_qhull = false, so a
// precision failure shows up as a failed test instead of a silent fallback.
#include "taskmap/quality/wrench_epsilon.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "quality_fixtures.hpp"

namespace taskmap {
namespace {

WrenchEpsilonOptions incrementalOnly(VolumeMode volume) {
  WrenchEpsilonOptions o;
  o.allow_qhull = false;
  o.volume = volume;
  return o;
}

/// Asserts that the incremental hull and qhull agree on force closure, epsilon (1e-9 relative)
/// and volume (1e-9 relative); returns whether the set is force closure.
bool expectAgreesWithQhull(const WrenchMatrix& w, const std::string& what) {
  const WrenchEpsilon e = wrenchEpsilon(w, incrementalOnly(VolumeMode::kAlways));
  const WrenchHull hull = wrenchHull(w);
  QualityResult q;
  summarizeHull(hull, q);
  EXPECT_EQ(e.status, q.status) << what << ": " << e.message;
  EXPECT_FALSE(e.used_qhull) << what;
  EXPECT_EQ(e.force_closure, q.force_closure) << what;
  EXPECT_NEAR(e.epsilon, q.epsilon, 1e-9 * q.epsilon) << what;
  EXPECT_NEAR(e.volume, q.volume, 1e-9 * q.volume) << what;
  // The lazy answer (no volume) is the same and never inserts more wrenches.
  const WrenchEpsilon lazy = wrenchEpsilon(w, incrementalOnly(VolumeMode::kNever));
  EXPECT_EQ(lazy.force_closure, e.force_closure) << what;
  EXPECT_EQ(lazy.epsilon, e.epsilon) << what;
  EXPECT_EQ(lazy.volume, 0.0);
  EXPECT_LE(lazy.inserted, e.inserted) << what;
  return q.force_closure;
}

/// n contacts on faces of the 10 x 6 x 4 cm box, up to 4 per face with the face's normal, the
/// way the simulator's contact manifold reports a finger link pressing a flat face: many
/// wrenches share hyperplanes exactly (the hard case for a hull without facet merging).
std::vector<Contact> flatFaceContacts(Rng& rng, int faces) {
  const Eigen::Vector3d half(0.05, 0.03, 0.02);
  std::vector<Contact> out;
  for (int f = 0; f < faces; ++f) {
    const int axis = static_cast<int>(rng.below(3));
    const double sign = rng.uniform() < 0.5 ? -1.0 : 1.0;
    const int per_face = 1 + static_cast<int>(rng.below(4));
    for (int k = 0; k < per_face; ++k) {
      Contact c;
      for (int i = 0; i < 3; ++i) c.point(i) = rng.uniform(-half(i), half(i));
      c.point(axis) = sign * half(axis);
      c.normal = sign * Eigen::Vector3d::Unit(axis);
      c.depth = 1e-3;
      c.link = f;
      out.push_back(c);
    }
  }
  return out;
}

TEST(WrenchEpsilonTest, SimplexAnalyticEpsilonAndVolume) {
  // The simplex of testing::simplexWrenches: epsilon 1/sqrt 41 (derived there).
  const WrenchMatrix w = testing::simplexWrenches();
  const WrenchEpsilon e = wrenchEpsilon(w, incrementalOnly(VolumeMode::kAlways));
  ASSERT_EQ(e.status, QualityStatus::kOk) << e.message;
  EXPECT_TRUE(e.force_closure);
  EXPECT_NEAR(e.epsilon, 1.0 / std::sqrt(41.0), 1e-14);
  EXPECT_NEAR(e.volume, testing::simplexVolume(w), 1e-14);
  EXPECT_EQ(e.inserted, 7);
}

TEST(WrenchEpsilonTest, CrossPolytopeNeedsEveryVertexAndHasEpsilonOneOverSqrt6) {
  // +-e_i: 64 facets sum s_i x_i = 1, all at distance 1/sqrt 6; volume 2^6 / 6! .
  WrenchMatrix w(6, 12);
  w.leftCols(6) = Eigen::Matrix<double, 6, 6>::Identity();
  w.rightCols(6) = -Eigen::Matrix<double, 6, 6>::Identity();
  const WrenchEpsilon e = wrenchEpsilon(w, incrementalOnly(VolumeMode::kAlways));
  ASSERT_EQ(e.status, QualityStatus::kOk) << e.message;
  EXPECT_NEAR(e.epsilon, 1.0 / std::sqrt(6.0), 1e-14);
  EXPECT_NEAR(e.volume, 64.0 / 720.0, 1e-14);
  EXPECT_EQ(e.facets, 64);
}

TEST(WrenchEpsilonTest, OriginOutsideOrOnTheBoundaryIsNotForceClosure) {
  // All wrenches in the half-space x_1 >= 0.1 (outside), then x_1 >= 0 with a face through
  // the origin (on the boundary): both not force closure, epsilon 0.
  Rng rng(3, 0);
  for (double shift : {0.1, 0.0}) {
    WrenchMatrix w(6, 20);
    for (Eigen::Index j = 0; j < w.cols(); ++j) {
      for (int i = 0; i < 6; ++i) w(i, j) = rng.uniform(-1.0, 1.0);
      w(0, j) = shift + (j < 10 ? 0.0 : rng.uniform(0.0, 1.0));
    }
    if (shift == 0.0) w.col(0).setZero();  // the origin itself, on the face x_1 = 0
    const WrenchEpsilon e = wrenchEpsilon(w, incrementalOnly(VolumeMode::kForceClosure));
    ASSERT_EQ(e.status, QualityStatus::kOk) << e.message;
    EXPECT_FALSE(e.force_closure) << "shift " << shift;
    EXPECT_EQ(e.epsilon, 0.0);
    EXPECT_EQ(e.volume, 0.0);  // kForceClosure: no volume for an open grasp
  }
}

TEST(WrenchEpsilonTest, DegenerateAndInvalidSetsAreReportedNotComputed) {
  WrenchMatrix flat = WrenchMatrix::Random(6, 30);
  flat.row(5).setConstant(0.25);  // affine rank 5
  WrenchEpsilon e = wrenchEpsilon(flat, incrementalOnly(VolumeMode::kAlways));
  EXPECT_EQ(e.status, QualityStatus::kDegenerate);
  EXPECT_NE(e.message.find("dimension 5"), std::string::npos) << e.message;
  e = wrenchEpsilon(WrenchMatrix::Random(6, 6));
  EXPECT_EQ(e.status, QualityStatus::kDegenerate);
  EXPECT_NE(e.message.find("7 needed"), std::string::npos) << e.message;
  WrenchMatrix bad = WrenchMatrix::Random(6, 12);
  bad(2, 3) = std::nan("");
  e = wrenchEpsilon(bad);
  EXPECT_EQ(e.status, QualityStatus::kInvalidInput);
  EXPECT_FALSE(e.force_closure);
}

TEST(WrenchEpsilonTest, AgreesWithQhullOnRandomConeSets) {
  int closures = 0, sets = 0;
  for (int n : {3, 4, 5, 6, 8, 10}) {
    for (int s = 0; s < 40; ++s) {
      Rng rng(515, static_cast<std::uint64_t>(100 * n + s));
      QualityOptions o;
      o.friction = rng.uniform(0.2, 1.0);
      if (s % 4 == 3) {
        o.contact_model = ContactModel::kSoftFinger;
        o.torsional_friction = 0.01;
      }
      const auto contacts = testing::randomContacts(rng, n, s % 2 ? 0.3 : 0.0);
      const auto w = contactWrenches(contacts, Eigen::Vector3d(0.002, 0.0, -0.001), 0.05, o);
      closures +=
          expectAgreesWithQhull(w, std::to_string(n) + " contacts, set " + std::to_string(s));
      ++sets;
    }
  }
  EXPECT_GT(closures, sets / 4);
  EXPECT_LT(closures, sets);
}

TEST(WrenchEpsilonTest, AgreesWithQhullOnFlatFaceManifoldContacts) {
  int closures = 0;
  for (int s = 0; s < 120; ++s) {
    Rng rng(616, static_cast<std::uint64_t>(s));
    const auto contacts = flatFaceContacts(rng, 2 + s % 4);
    const auto w = contactWrenches(contacts, Eigen::Vector3d::Zero(), 0.06);
    std::string message;
    double scale = 0.0;
    if (screenWrenches(w, true, scale, message) != QualityStatus::kOk) continue;
    closures += expectAgreesWithQhull(w, "flat-face set " + std::to_string(s));
  }
  EXPECT_GT(closures, 10);
}

TEST(WrenchEpsilonTest, AgreesWithQhullOnSimulatedBasketGrasps) {
  // Contacts recorded from the reference build (basket, Barrett hand): up to 4 contacts per
  // finger link on the basket's flat faces, the case that breaks hulls without merging.
  const std::string path = std::string(TEST_DATA_DIR) + "/quality/basket_barrett_contacts.txt";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  std::string line;
  std::stringstream body;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#') body << line << '\n';
  }
  Eigen::Vector3d com;
  double torque_scale = 0.0;
  body >> com.x() >> com.y() >> com.z() >> torque_scale;
  int n = 0, grasps = 0, closures = 0;
  while (body >> n) {
    std::vector<Contact> contacts(static_cast<std::size_t>(n));
    for (Contact& c : contacts) {
      body >> c.point.x() >> c.point.y() >> c.point.z() >> c.normal.x() >> c.normal.y() >>
          c.normal.z() >> c.depth;
    }
    const auto w = contactWrenches(contacts, com, torque_scale);
    closures += expectAgreesWithQhull(w, "basket grasp " + std::to_string(grasps));
    ++grasps;
  }
  EXPECT_EQ(grasps, 150);
  EXPECT_EQ(closures, grasps);  // the build stored force-closure grasps only
}

TEST(WrenchEpsilonTest, EvaluateGraspVolumeModes) {
  Rng rng(9, 1);
  int open = 0, closed = 0;
  for (int s = 0; s < 30; ++s) {
    const auto contacts = testing::randomContacts(rng, 4, 0.2);
    QualityOptions o;
    o.volume = VolumeMode::kAlways;
    const QualityResult always = evaluateGrasp(contacts, Eigen::Vector3d::Zero(), 0.05, o);
    o.volume = VolumeMode::kForceClosure;
    const QualityResult fc = evaluateGrasp(contacts, Eigen::Vector3d::Zero(), 0.05, o);
    o.volume = VolumeMode::kNever;
    const QualityResult never = evaluateGrasp(contacts, Eigen::Vector3d::Zero(), 0.05, o);
    ASSERT_EQ(always.status, QualityStatus::kOk) << always.message;
    EXPECT_GT(always.volume, 0.0);
    EXPECT_EQ(fc.volume, always.force_closure ? always.volume : 0.0);
    EXPECT_EQ(never.volume, 0.0);
    EXPECT_EQ(fc.epsilon, always.epsilon);
    EXPECT_EQ(never.epsilon, always.epsilon);
    (always.force_closure ? closed : open)++;
  }
  EXPECT_GT(open, 0);
  EXPECT_GT(closed, 0);
}

}  // namespace
}  // namespace taskmap
