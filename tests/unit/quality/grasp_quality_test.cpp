// Unit tests of taskmap::evaluateGrasp / contactWrenches: options, cone edges, analytic
// grasps, degenerate input, invariances, concurrency, L-infinity. (wrench_hull_test.cpp: the
// hull itself and qhull's silence.)
#include "taskmap/quality/grasp_quality.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "error_matchers.hpp"
#include "quality_fixtures.hpp"
#include "taskmap/core/constants.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/quality/wrench_hull.hpp"

namespace taskmap {
namespace {

using testing::makeContact;
using testing::randomContacts;

// ---------------------------------------------------------------------------------------------
// Options, names

TEST(QualityOptionsTest, DefaultsAreValidAndFollowGraspIt) {
  QualityOptions o;
  EXPECT_NO_THROW(o.validate());
  EXPECT_EQ(o.friction, 0.5);
  EXPECT_EQ(o.cone_edges, 8);
  EXPECT_EQ(o.contact_model, ContactModel::kPointWithFriction);
  EXPECT_EQ(o.norm, WrenchNorm::kL1);
}

TEST(QualityOptionsTest, ValidateNamesTheBadOption) {
  QualityOptions o;
  o.friction = -0.1;
  EXPECT_TRUE(taskmap::testing::throwsError([&] { o.validate(); }, {"friction"}));
  o = {};
  o.friction = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(taskmap::testing::throwsError([&] { o.validate(); }, {"friction"}));
  o = {};
  o.cone_edges = 2;
  EXPECT_TRUE(taskmap::testing::throwsError([&] { o.validate(); }, {"cone_edges"}));
  o = {};
  o.torsional_friction = -1.0;
  EXPECT_TRUE(taskmap::testing::throwsError([&] { o.validate(); }, {"torsional_friction"}));
  o = {};
  o.max_linf_contacts = 0;
  EXPECT_TRUE(taskmap::testing::throwsError([&] { o.validate(); }, {"max_linf_contacts"}));
  o = {};
  o.volume = static_cast<VolumeMode>(7);
  EXPECT_TRUE(taskmap::testing::throwsError([&] { o.validate(); }, {"volume"}));
  // evaluateGrasp validates too.
  o = {};
  o.cone_edges = 1;
  std::vector<Contact> none;
  EXPECT_TRUE(taskmap::testing::throwsError(
      [&] { evaluateGrasp(none, Eigen::Vector3d::Zero(), 0.1, o); }, {"cone_edges"}));
}

TEST(QualityOptionsTest, TorqueScaleMustBePositiveAndFinite) {
  std::vector<Contact> one{makeContact({0, 0, 1}, {0, 0, 1})};
  for (double r : {0.0, -1.0, std::numeric_limits<double>::infinity(),
                   std::numeric_limits<double>::quiet_NaN()}) {
    EXPECT_TRUE(taskmap::testing::throwsError(
        [&] { evaluateGrasp(one, Eigen::Vector3d::Zero(), r); }, {"torque_scale"}));
    EXPECT_TRUE(taskmap::testing::throwsError(
        [&] { contactWrenches(one, Eigen::Vector3d::Zero(), r); }, {"torque_scale"}));
  }
}

TEST(QualityNamesTest, StatusAndContactModelNames) {
  EXPECT_STREQ(toString(QualityStatus::kOk), "ok");
  EXPECT_STREQ(toString(QualityStatus::kNoContacts), "no_contacts");
  EXPECT_STREQ(toString(QualityStatus::kDegenerate), "degenerate");
  EXPECT_STREQ(toString(QualityStatus::kInvalidInput), "invalid_input");
  EXPECT_STREQ(toString(QualityStatus::kHullFailed), "hull_failed");
  for (ContactModel m : {ContactModel::kPointWithFriction, ContactModel::kSoftFinger}) {
    EXPECT_EQ(contactModelFromString(toString(m)), m);
  }
  EXPECT_TRUE(taskmap::testing::throwsError([] { contactModelFromString("hard"); }, {"'hard'"}));
}

// ---------------------------------------------------------------------------------------------
// Cone edges

TEST(ContactWrenchesTest, EdgesFollowGraspItConvention) {
  Rng rng(3, 0);
  const Eigen::Vector3d com(0.01, -0.005, 0.002);
  const double r = 0.07;
  QualityOptions o;
  o.friction = 0.4;
  o.cone_edges = 7;
  const auto contacts = randomContacts(rng, 3);
  const auto w = contactWrenches(contacts, com, r, o);
  ASSERT_EQ(w.cols(), 3 * 7);
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d n = contacts[i].normal.normalized();
    const Eigen::Vector3d lever = contacts[i].point - com;
    // Tangent t1 points from the contact towards the centre of mass within the tangent plane.
    const Eigen::Vector3d toward = (-lever - (-lever).dot(n) * n).normalized();
    for (int j = 0; j < 7; ++j) {
      const Eigen::Vector3d f = w.col(i * 7 + j).head<3>();
      const Eigen::Vector3d tau = w.col(i * 7 + j).tail<3>();
      EXPECT_NEAR(f.dot(-n), 1.0, 1e-12);              // unit force into the object
      EXPECT_NEAR((f + n).norm(), o.friction, 1e-12);  // plus mu times a unit tangent
      EXPECT_NEAR((f + n).dot(n), 0.0, 1e-12);
      // Equally spaced angles from t1.
      const double angle = std::atan2((f + n).dot(n.cross(toward)), (f + n).dot(toward));
      double expected = 2.0 * kPi * j / 7;
      if (expected > kPi) expected -= 2.0 * kPi;
      EXPECT_NEAR(angle, expected, 1e-12);
      EXPECT_LT((tau - lever.cross(f) / r).norm(), 1e-12);
    }
  }
}

TEST(ContactWrenchesTest, FallbackBasisWhenNormalPassesThroughCentre) {
  // Contact on a sphere: c - p is parallel to n, so t1 = normalise(n x e_k), k the smallest
  // |component| of n. n = (0.6, 0.8, 0) -> k = 2 (z), t1 = n x e_z = (0.8, -0.6, 0).
  const Contact c = makeContact({0.6, 0.8, 0.0}, {0.6, 0.8, 0.0});
  QualityOptions o;
  o.friction = 1.0;
  const auto w = contactWrenches({c}, Eigen::Vector3d::Zero(), 1.0, o);
  const Eigen::Vector3d t1 = w.col(0).head<3>() + c.normal;
  EXPECT_LT((t1 - Eigen::Vector3d(0.8, -0.6, 0.0)).norm(), 1e-12);
}

TEST(ContactWrenchesTest, SkipsContactsWithoutPressure) {
  std::vector<Contact> c{makeContact({0, 0, 1}, {0, 0, 1}, 0.0),
                         makeContact({0, 1, 0}, {0, 1, 0}, 1e-3),
                         makeContact({1, 0, 0}, {1, 0, 0}, -1e-3)};
  const auto w = contactWrenches(c, Eigen::Vector3d::Zero(), 1.0);
  ASSERT_EQ(w.cols(), 8);
  EXPECT_NEAR(w(1, 0), -1.0, 1e-12);  // only the y contact
}

TEST(ContactWrenchesTest, SoftFingerAddsTwoTorsionEdges) {
  QualityOptions o;
  o.contact_model = ContactModel::kSoftFinger;
  o.torsional_friction = 0.01;
  const Contact c = makeContact({0, 0, 0.1}, {0, 0, 1});
  const auto w = contactWrenches({c}, Eigen::Vector3d::Zero(), 0.1, o);
  ASSERT_EQ(w.cols(), 10);
  Eigen::Matrix<double, 6, 1> plus, minus;
  plus << 0, 0, -1, 0, 0, 0.01 / 0.1;
  minus << 0, 0, -1, 0, 0, -0.01 / 0.1;
  EXPECT_LT((w.col(8) - plus).norm(), 1e-12);
  EXPECT_LT((w.col(9) - minus).norm(), 1e-12);
  o.torsional_friction = 0.0;  // no torsion: same as a point contact
  EXPECT_EQ(contactWrenches({c}, Eigen::Vector3d::Zero(), 0.1, o).cols(), 8);
}

// ---------------------------------------------------------------------------------------------
// Degenerate and invalid input: defined results, never a crash.

TEST(EvaluateGraspTest, NoContactsAndNoPressure) {
  auto r = evaluateGrasp({}, Eigen::Vector3d::Zero(), 1.0);
  EXPECT_EQ(r.status, QualityStatus::kNoContacts);
  EXPECT_FALSE(r.force_closure);
  EXPECT_EQ(r.epsilon, 0.0);
  r = evaluateGrasp({makeContact({0, 0, 1}, {0, 0, 1}, 0.0)}, Eigen::Vector3d::Zero(), 1.0);
  EXPECT_EQ(r.status, QualityStatus::kNoContacts);
  EXPECT_EQ(r.contacts_used, 0);
  EXPECT_NE(r.message.find("pressure"), std::string::npos);
}

TEST(EvaluateGraspTest, OneContactIsDegenerate) {
  // 8 edge wrenches of one contact lie in a 2-D affine plane.
  const auto r = evaluateGrasp({makeContact({0, 0, 1}, {0, 0, 1})}, Eigen::Vector3d::Zero(), 1.0);
  EXPECT_EQ(r.status, QualityStatus::kDegenerate);
  EXPECT_EQ(r.contacts_used, 1);
  EXPECT_FALSE(r.force_closure);
  EXPECT_EQ(r.epsilon, 0.0);
  EXPECT_EQ(r.volume, 0.0);
  EXPECT_FALSE(r.message.empty());
}

TEST(EvaluateGraspTest, NonFiniteOrZeroNormalIsInvalidInput) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  Rng rng(5, 0);
  const auto base = randomContacts(rng, 4);
  auto check = [&](std::vector<Contact> c, Eigen::Vector3d com, const std::string& needle) {
    const auto r = evaluateGrasp(c, com, 0.05);
    EXPECT_EQ(r.status, QualityStatus::kInvalidInput) << needle;
    EXPECT_FALSE(r.force_closure);
    EXPECT_EQ(r.epsilon, 0.0);
    EXPECT_NE(r.message.find(needle), std::string::npos) << r.message;
  };
  auto c = base;
  c[2].point.x() = nan;
  check(c, Eigen::Vector3d::Zero(), "contact 2");
  c = base;
  c[1].normal.z() = inf;
  check(c, Eigen::Vector3d::Zero(), "contact 1");
  c = base;
  c[3].depth = nan;
  check(c, Eigen::Vector3d::Zero(), "contact 3");
  c = base;
  c[0].normal.setZero();
  check(c, Eigen::Vector3d::Zero(), "zero normal");
  check(base, Eigen::Vector3d(nan, 0, 0), "centre of mass");
  // A zero normal on a contact without pressure is ignored.
  c = base;
  c.push_back(makeContact({0, 0, 0}, {0, 0, 1}, 0.0));
  c.back().normal.setZero();
  EXPECT_NE(evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05).status, QualityStatus::kInvalidInput);
}

TEST(EvaluateGraspTest, FrictionlessContactsOnASphereAreDegenerate) {
  // Every normal passes through the centre: all torques vanish, wrenches span 3 dimensions.
  Rng rng(11, 0);
  std::vector<Contact> c;
  for (int i = 0; i < 12; ++i) {
    const Eigen::Vector3d d = rng.direction();
    c.push_back(makeContact(0.05 * d, d));
  }
  QualityOptions o;
  o.friction = 0.0;
  const auto r = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05, o);
  EXPECT_EQ(r.status, QualityStatus::kDegenerate);
  EXPECT_FALSE(r.force_closure);
  EXPECT_NE(r.message.find("dimension 3"), std::string::npos) << r.message;
}

TEST(EvaluateGraspTest, CollinearContactsAreDegenerate) {
  // Points on the x axis through c: (p x f)_x = p_y f_z - p_z f_y = 0 for every force, so the
  // torque about x is never produced: rank <= 5 whatever the normals and friction.
  Rng rng(12, 0);
  std::vector<Contact> c;
  for (int i = 0; i < 6; ++i) {
    c.push_back(makeContact({rng.uniform(-0.05, 0.05), 0, 0}, rng.direction()));
  }
  const auto r = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05);
  EXPECT_EQ(r.status, QualityStatus::kDegenerate);
  EXPECT_FALSE(r.force_closure);
}

TEST(EvaluateGraspTest, PlanarFrictionlessGraspIsDegenerate) {
  // Points and normals in the plane z = 0, no friction: forces in the plane, torques along z:
  // rank 3.
  std::vector<Contact> c;
  for (int i = 0; i < 8; ++i) {
    const double a = 2.0 * kPi * i / 8 + 0.1;
    c.push_back(
        makeContact({std::cos(a), std::sin(a), 0}, {std::cos(a + 0.3), std::sin(a + 0.3), 0}));
  }
  QualityOptions o;
  o.friction = 0.0;
  const auto r = evaluateGrasp(c, Eigen::Vector3d::Zero(), 1.0, o);
  EXPECT_EQ(r.status, QualityStatus::kDegenerate);
}

TEST(EvaluateGraspTest, TwoAntipodalPointContactsAreDegenerate) {
  // Forces at points on the contact axis exert no torque about that axis: rank 5.
  std::vector<Contact> c{makeContact({0, 0, 0.03}, {0, 0, 1}),
                         makeContact({0, 0, -0.03}, {0, 0, -1})};
  const auto r = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.03);
  EXPECT_EQ(r.status, QualityStatus::kDegenerate);
  EXPECT_FALSE(r.force_closure);
}

TEST(EvaluateGraspTest, TwoAntipodalSoftFingersAreForceClosure) {
  // (a) Positive weights sum to 0: each contact's edges average to its normal wrench (-n, 0)
  //     (tangents and +-torsion cancel; the normal force has no moment about c on the axis),
  //     and the two antipodal normal wrenches cancel.
  // (b) Rank 6: forces along the axis and both tangents; torques about both transverse axes
  //     from the tangential forces at +-0.03; torque about the axis from torsion.
  // So the origin is strictly inside the hull.
  std::vector<Contact> c{makeContact({0, 0, 0.03}, {0, 0, 1}),
                         makeContact({0, 0, -0.03}, {0, 0, -1})};
  QualityOptions o;
  o.contact_model = ContactModel::kSoftFinger;
  o.torsional_friction = 0.005;
  const auto r = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.03, o);
  EXPECT_EQ(r.status, QualityStatus::kOk) << r.message;
  EXPECT_TRUE(r.force_closure);
  EXPECT_GT(r.epsilon, 0.0);
  EXPECT_GT(r.volume, 0.0);
  EXPECT_EQ(r.contacts_used, 2);
}

TEST(EvaluateGraspTest, ThreeContactsOnSphereEquatorNeedFriction) {
  // Contacts at 120 degrees on the equator of a sphere about c. With mu > 0: (a) the normal
  // wrenches (-n_i, 0) (edge averages) sum to zero with equal weights, (b) friction gives forces
  // along z and in the plane, and torques about z (in-plane tangents) and about x, y (vertical
  // tangents at different points): rank 6 -> force closure. With mu = 0 all torques vanish
  // (rank 2: forces in the plane only) -> degenerate.
  std::vector<Contact> c;
  for (int i = 0; i < 3; ++i) {
    const double a = 2.0 * kPi * i / 3;
    const Eigen::Vector3d d(std::cos(a), std::sin(a), 0);
    c.push_back(makeContact(0.04 * d, d));
  }
  QualityOptions o;
  for (double mu : {0.1, 0.5, 1.0}) {
    o.friction = mu;
    const auto r = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.04, o);
    EXPECT_EQ(r.status, QualityStatus::kOk) << r.message;
    EXPECT_TRUE(r.force_closure) << "mu = " << mu;
    EXPECT_GT(r.epsilon, 0.0);
  }
  o.friction = 0.0;
  const auto r = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.04, o);
  EXPECT_EQ(r.status, QualityStatus::kDegenerate);
  EXPECT_FALSE(r.force_closure);
}

TEST(EvaluateGraspTest, ContactsOnOneFaceAreDegenerate) {
  // Four contacts on the top face z = 0.02 of a box, normal +z: every edge force has
  // f_z = -1, so all wrenches lie in the affine hyperplane f_z = -1 (affine rank 5), which
  // misses the origin: degenerate, not force closure.
  std::vector<Contact> c;
  for (double x : {-0.03, 0.03}) {
    for (double y : {-0.02, 0.02}) c.push_back(makeContact({x, y, 0.02}, {0, 0, 1}));
  }
  const auto r = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05);
  EXPECT_EQ(r.status, QualityStatus::kDegenerate) << r.message;
  EXPECT_FALSE(r.force_closure);
  EXPECT_EQ(r.epsilon, 0.0);
}

TEST(EvaluateGraspTest, ContactsOnTwoAdjacentFacesAreNotForceClosure) {
  // Contacts on the top face (normal e_z) and the side face x = 0.05 (normal e_x), mu = 0.5.
  // For u = (e_x + e_z, 0): a top edge force f = -e_z + mu t (t _|_ e_z, |t| = 1) gives
  // u . w = -1 + mu t_x <= -0.5, a side edge -1 + mu t_z <= -0.5. All wrenches lie strictly on
  // one side of a hyperplane through the origin: not force closure. They span 6 dimensions,
  // so the status is ok and epsilon 0; the volume is 0 by default (VolumeMode::kForceClosure)
  // and positive when asked for always.
  std::vector<Contact> c;
  for (double x : {-0.03, 0.03}) c.push_back(makeContact({x, 0.01, 0.02}, {0, 0, 1}));
  for (double y : {-0.02, 0.02}) c.push_back(makeContact({0.05, y, -0.01}, {1, 0, 0}));
  const auto r = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05);
  EXPECT_EQ(r.status, QualityStatus::kOk) << r.message;
  EXPECT_FALSE(r.force_closure);
  EXPECT_EQ(r.epsilon, 0.0);
  EXPECT_EQ(r.volume, 0.0);
  QualityOptions always;
  always.volume = VolumeMode::kAlways;
  const auto v = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05, always);
  EXPECT_FALSE(v.force_closure);
  EXPECT_GT(v.volume, 0.0);
}

TEST(EvaluateGraspTest, CubeWithTwentyFourFrictionlessContactsHasEpsilonOneOverSqrt3) {
  // Cube [-1, 1]^3, c = 0, torque scale r = 0.5, mu = 0. On face x = +1 (force -e_x) contacts
  // at (1, 0, +-0.5) and (1, +-0.5, 0) give torques p x f / r = (0, -z, y) / 0.5 = -+e_y, +-e_z.
  // Over the six faces the wrench set is W = {(s e_k, t e_l) : k != l, s, t = +-1}, 24 points.
  // Support function: h(u) = max_{w in W} u . w = max_{k != l} |f_k| + |tau_l| for u = (f, tau).
  // epsilon = min_{|u| = 1} h(u):
  //  * u = (1, 1, 1, 0, 0, 0) / sqrt 3 gives h = 1 / sqrt 3, so epsilon <= 1 / sqrt 3.
  //  * Lower bound. Let F1 = max|f_k| (index k1), T1 = max|tau_l| (index l1).
  //    If k1 != l1: h >= F1 + T1 >= sqrt(F1^2 + T1^2) >= sqrt((|f|^2 + |tau|^2) / 3) = 1/sqrt 3.
  //    If k1 == l1: let F2, T2 be the largest |f|, |tau| over the other two indices. Then
  //    h >= F1 + T2 and h >= F2 + T1, and 1 <= F1^2 + 2 F2^2 + T1^2 + 2 T2^2. Since
  //    x^2 + 2y^2 = (x + y)^2 - 2xy + y^2 <= (x + y)^2 + y^2 for x, y >= 0:
  //    F1^2 + 2 T2^2 <= h^2 + T2^2 and T1^2 + 2 F2^2 <= h^2 + F2^2, and T2 + F2 <= T1 + F2 <= h,
  //    so 1 <= 2 h^2 + (T2 + F2)^2 <= 3 h^2, i.e. h >= 1 / sqrt 3.
  //  Hence epsilon = 1 / sqrt 3 exactly, and the grasp is force closure.
  std::vector<Contact> c;
  for (int k = 0; k < 3; ++k) {
    for (double s : {-1.0, 1.0}) {
      const Eigen::Vector3d n = s * Eigen::Vector3d::Unit(k);
      for (int l = 0; l < 3; ++l) {
        if (l == k) continue;
        for (double t : {-0.5, 0.5}) c.push_back(makeContact(n + t * Eigen::Vector3d::Unit(l), n));
      }
    }
  }
  ASSERT_EQ(c.size(), 24u);
  QualityOptions o;
  o.friction = 0.0;
  const auto r = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.5, o);
  EXPECT_EQ(r.status, QualityStatus::kOk) << r.message;
  EXPECT_TRUE(r.force_closure);
  EXPECT_NEAR(r.epsilon, 1.0 / std::sqrt(3.0), 1e-12);
  EXPECT_EQ(r.contacts_used, 24);
}

TEST(EvaluateGraspTest, DuplicateContactsChangeNothing) {
  // Duplicated contacts duplicate wrenches; the hull (and so epsilon and volume) is the same.
  Rng rng(21, 0);
  int closures = 0;
  for (int trial = 0; trial < 10; ++trial) {
    auto c = randomContacts(rng, 4);
    const auto once = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05);
    c.push_back(c[0]);
    c.push_back(c[2]);
    const auto twice = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05);
    EXPECT_EQ(once.status, twice.status);
    EXPECT_EQ(once.force_closure, twice.force_closure);
    EXPECT_NEAR(once.epsilon, twice.epsilon, 1e-12);
    EXPECT_NEAR(once.volume, twice.volume, 1e-9 * std::max(once.volume, 1e-300));
    EXPECT_EQ(twice.contacts_used, 6);
    closures += once.force_closure;
  }
  EXPECT_GT(closures, 0);
}

// ---------------------------------------------------------------------------------------------
// Invariances

TEST(EvaluateGraspTest, EpsilonInvariantUnderRigidMotionOfContactsAndObject) {
  // The cone basis is built from n and (c - p), both covariant, and wrenches transform by
  // diag(R, R) (orthogonal), so epsilon and volume are unchanged.
  Rng rng(31, 0);
  int closures = 0;
  for (int trial = 0; trial < 16; ++trial) {
    const auto c = randomContacts(rng, 4 + trial % 3, 0.2);
    const Eigen::Vector3d com(0.004, -0.002, 0.001);
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    motion.linear() = rng.rotation().toRotationMatrix();
    motion.translation() =
        Eigen::Vector3d(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const auto a = evaluateGrasp(c, com, 0.05);
    const auto b = evaluateGrasp(testing::moved(c, motion), motion * com, 0.05);
    EXPECT_EQ(a.status, b.status);
    EXPECT_EQ(a.force_closure, b.force_closure);
    EXPECT_NEAR(a.epsilon, b.epsilon, 1e-9 * std::max(a.epsilon, 1e-3));
    EXPECT_NEAR(a.volume, b.volume, 1e-8 * a.volume);
    closures += a.force_closure;
  }
  EXPECT_GT(closures, 2);
}

TEST(EvaluateGraspTest, EpsilonNonDecreasingInFriction) {
  // Edges at mu' < mu are convex combinations of the edges at mu (the edges average to -n),
  // so the hull only grows with mu.
  Rng rng(41, 0);
  int increased = 0;
  for (int trial = 0; trial < 8; ++trial) {
    const auto c = randomContacts(rng, 4, 0.1);
    double last = 0.0;
    for (double mu : {0.1, 0.3, 0.5, 0.8, 1.2}) {
      QualityOptions o;
      o.friction = mu;
      const auto r = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05, o);
      EXPECT_GE(r.epsilon, last - 1e-12) << "mu = " << mu;
      increased += r.epsilon > last + 1e-9;
      last = r.epsilon;
    }
  }
  EXPECT_GT(increased, 4);
}

// ---------------------------------------------------------------------------------------------
// Concurrency

TEST(EvaluateGraspTest, ThreadsGiveTheSameResultsAsSequential) {
  Rng rng(61, 0);
  std::vector<std::vector<Contact>> sets;
  for (int i = 0; i < 12; ++i) sets.push_back(randomContacts(rng, 3 + i % 3, 0.1));
  std::vector<QualityResult> seq;
  for (const auto& s : sets) seq.push_back(evaluateGrasp(s, Eigen::Vector3d::Zero(), 0.05));
  const int threads = 4;
  std::vector<std::vector<QualityResult>> par(threads, std::vector<QualityResult>(sets.size()));
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      // Every thread scores every set, in a different order.
      for (std::size_t k = 0; k < sets.size(); ++k) {
        const std::size_t i = (k + 7 * t) % sets.size();
        par[t][i] = evaluateGrasp(sets[i], Eigen::Vector3d::Zero(), 0.05);
      }
    });
  }
  for (auto& th : pool) th.join();
  for (int t = 0; t < threads; ++t) {
    for (std::size_t i = 0; i < sets.size(); ++i) {
      EXPECT_EQ(par[t][i].status, seq[i].status);
      EXPECT_EQ(par[t][i].force_closure, seq[i].force_closure);
      EXPECT_EQ(par[t][i].epsilon, seq[i].epsilon);  // bitwise: no shared state
      EXPECT_EQ(par[t][i].volume, seq[i].volume);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// L-infinity

TEST(EvaluateGraspTest, LInfIsTheHullOfTheMinkowskiSum) {
  // LInf: hull of the Minkowski sum of the sets {0} u edges_i (normal force in [0, 1] on every
  // contact). It contains the L1 hull (the union of the edges: all other contacts at 0), so its
  // epsilon is at least the L1 epsilon, and the origin is inside exactly when it is for L1.
  Rng rng(71, 0);
  QualityOptions o;
  o.norm = WrenchNorm::kLInf;
  o.cone_edges = 4;
  o.friction = 1.0;
  o.volume = VolumeMode::kAlways;
  QualityOptions l1 = o;
  l1.norm = WrenchNorm::kL1;
  int closures = 0;
  for (int trial = 0; trial < 10; ++trial) {
    const int n = 3;
    const auto c = randomContacts(rng, n);
    const auto edges = contactWrenches(c, Eigen::Vector3d::Zero(), 0.05, o);
    // Every choice (nothing or one edge per contact), enumerated independently.
    WrenchMatrix sum(6, 125);
    for (int k = 0; k < 125; ++k) {
      sum.col(k).setZero();
      for (int i = 0, code = k; i < n; ++i, code /= 5) {
        if (code % 5) sum.col(k) += edges.col(4 * i + code % 5 - 1);
      }
    }
    QualityResult expected;
    summarizeHull(wrenchHull(sum), expected);
    const auto r = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05, o);
    EXPECT_EQ(r.status, expected.status);
    EXPECT_EQ(r.force_closure, expected.force_closure);
    EXPECT_NEAR(r.epsilon, expected.epsilon, 1e-12);
    EXPECT_NEAR(r.volume, expected.volume, 1e-9 * std::max(expected.volume, 1e-300));
    const auto r1 = evaluateGrasp(c, Eigen::Vector3d::Zero(), 0.05, l1);
    EXPECT_EQ(r.force_closure, r1.force_closure);
    EXPECT_GE(r.epsilon, r1.epsilon - 1e-12);
    closures += r.force_closure;
  }
  EXPECT_GT(closures, 0);
}

TEST(EvaluateGraspTest, LInfRefusesLargeContactSets) {
  Rng rng(72, 0);
  QualityOptions o;
  o.norm = WrenchNorm::kLInf;
  o.max_linf_contacts = 3;
  const auto r = evaluateGrasp(randomContacts(rng, 4), Eigen::Vector3d::Zero(), 0.05, o);
  EXPECT_EQ(r.status, QualityStatus::kInvalidInput);
  EXPECT_NE(r.message.find("max_linf_contacts"), std::string::npos) << r.message;
}

}  // namespace
}  // namespace taskmap
