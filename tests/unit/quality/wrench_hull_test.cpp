// Unit tests of taskmap::wrenchHull / summarizeHull: volume and facets, degenerate sets, the
// verified fast pass against qhull's merging pass, and qhull's silence.
#include "taskmap/quality/wrench_hull.hpp"

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "quality_fixtures.hpp"
#include "taskmap/quality/grasp_quality.hpp"

extern "C" {
#include <libqhull_r/qhull_ra.h>  // only for the precondition of the silence test
}

namespace taskmap {
namespace {

using testing::makeContact;
using testing::randomContacts;

// ---------------------------------------------------------------------------------------------
// wrenchHull directly

TEST(WrenchHullTest, SimplexVolumeAndEpsilon) {
  // The simplex of testing::simplexWrenches (facets and epsilon 1/sqrt 41 derived there).
  const WrenchMatrix w = testing::simplexWrenches();
  const double volume = testing::simplexVolume(w);
  const auto h = wrenchHull(w);
  ASSERT_EQ(h.status, QualityStatus::kOk) << h.message;
  EXPECT_EQ(h.offsets.size(), 7);
  EXPECT_NEAR(h.volume, volume, 1e-12 * volume);
  QualityResult r;
  summarizeHull(h, r);
  EXPECT_TRUE(r.force_closure);
  EXPECT_NEAR(r.epsilon, 1.0 / std::sqrt(41.0), 1e-12);
  // Every facet normal is unit and every vertex lies on or inside every facet.
  for (int f = 0; f < h.offsets.size(); ++f) {
    EXPECT_NEAR(h.normals.col(f).norm(), 1.0, 1e-12);
    EXPECT_LE((h.normals.col(f).transpose() * w).maxCoeff() + h.offsets(f), 1e-12);
  }
}

TEST(WrenchHullTest, FlatAndTooSmallSetsAreDegenerate) {
  WrenchMatrix w = WrenchMatrix::Random(6, 20);
  w.row(3) = 0.5 * w.row(1) - w.row(2);  // affine rank 5
  auto h = wrenchHull(w);
  EXPECT_EQ(h.status, QualityStatus::kDegenerate);
  EXPECT_NE(h.message.find("dimension 5"), std::string::npos) << h.message;
  h = wrenchHull(WrenchMatrix::Random(6, 6));
  EXPECT_EQ(h.status, QualityStatus::kDegenerate);
  h = wrenchHull(WrenchMatrix(6, 0));
  EXPECT_EQ(h.status, QualityStatus::kDegenerate);
  WrenchMatrix bad = WrenchMatrix::Random(6, 10);
  bad(4, 4) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(wrenchHull(bad).status, QualityStatus::kInvalidInput);
}

TEST(WrenchHullTest, FastPassAgreesWithMergingPass) {
  // The unmerged "Q0" pass is accepted only after verification; it must give the same epsilon
  // and volume as qhull's merging "Qx" pass.
  Rng rng(81, 0);
  int closures = 0;
  for (int trial = 0; trial < 12; ++trial) {
    QualityOptions o;
    o.friction = rng.uniform(0.2, 1.0);
    o.cone_edges = 4 + trial % 5;
    const auto w =
        contactWrenches(randomContacts(rng, 3 + trial % 3, 0.2), Eigen::Vector3d::Zero(), 0.05, o);
    const WrenchHull fast = wrenchHull(w);
    WrenchHullOptions merged_only;
    merged_only.fast_pass = false;
    const WrenchHull merged = wrenchHull(w, merged_only);
    ASSERT_EQ(fast.status, QualityStatus::kOk);
    ASSERT_EQ(merged.status, QualityStatus::kOk);
    EXPECT_TRUE(merged.merged_pass);
    QualityResult a, b;
    summarizeHull(fast, a);
    summarizeHull(merged, b);
    EXPECT_EQ(a.force_closure, b.force_closure);
    EXPECT_NEAR(a.epsilon, b.epsilon, 1e-10 * std::max(b.epsilon, 1e-3));
    EXPECT_NEAR(a.volume, b.volume, 1e-9 * b.volume);
    closures += a.force_closure;
  }
  EXPECT_GT(closures, 0);
}

// ---------------------------------------------------------------------------------------------
// Silence

/// 20 wrenches in a 5-D affine subspace: qhull fails on it ("initial simplex is flat").
WrenchMatrix flatWrenches() {
  Rng rng(52, 0);
  WrenchMatrix w(6, 20);
  for (int j = 0; j < 20; ++j) {
    for (int i = 0; i < 6; ++i) w(i, j) = rng.uniform(-1, 1);
    w(3, j) = 0.5 * w(1, j) - w(2, j) + 0.25;
  }
  return w;
}

TEST(WrenchHullTest, QhullPrintsOnAFlatSetWhenGivenStderr) {
  // Precondition of QhullNeverPrints: the flat set makes qhull itself talk, and the capture
  // sees it. (Calls qhull directly with errfile = stderr.)
  WrenchMatrix w = flatWrenches();
  ::testing::internal::CaptureStderr();
  qhT qh;
  qh_zero(&qh, stderr);
  char flags[] = "qhull Qx FA";
  const int code =
      qh_new_qhull(&qh, 6, static_cast<int>(w.cols()), w.data(), False, flags, nullptr, stderr);
  qh_freeqhull(&qh, !qh_ALL);
  int curlong = 0, totlong = 0;
  qh_memfreeshort(&qh, &curlong, &totlong);
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(code, 0);
  EXPECT_NE(err.find("QH6154"), std::string::npos) << err.substr(0, 200);
}

TEST(WrenchHullTest, QhullNeverPrints) {
  // Degenerate, nearly degenerate, failing and heavily merged inputs; nothing may reach
  // stdout or stderr.
  Rng rng(51, 0);
  std::vector<std::vector<Contact>> sets;
  sets.push_back({});
  sets.push_back(randomContacts(rng, 1));
  sets.push_back(randomContacts(rng, 2));
  auto dup = randomContacts(rng, 3);
  dup.push_back(dup[1]);
  sets.push_back(dup);
  std::vector<Contact> thin;  // nearly collinear
  for (int i = 0; i < 5; ++i) {
    thin.push_back(
        makeContact({0.01 * i, 1e-6 * rng.uniform(), 1e-6 * rng.uniform()}, rng.direction()));
  }
  sets.push_back(thin);
  for (int i = 0; i < 10; ++i) sets.push_back(randomContacts(rng, 3 + i % 5));
  WrenchMatrix nearly_flat = WrenchMatrix::Random(6, 30);
  nearly_flat.row(5) = 1e-6 * nearly_flat.row(5);
  WrenchMatrix huge = WrenchMatrix::Random(6, 40);
  huge.col(3) *= 1e200;

  ::testing::internal::CaptureStdout();
  ::testing::internal::CaptureStderr();
  for (const auto& s : sets) evaluateGrasp(s, Eigen::Vector3d::Zero(), 0.05);
  const WrenchHull a = wrenchHull(nearly_flat);
  const WrenchHull b = wrenchHull(flatWrenches(), {/*check_rank=*/false});  // qhull error path
  const WrenchHull c = wrenchHull(huge, {/*check_rank=*/false});            // qhull error path
  const WrenchHull d = wrenchHull(huge);
  const std::string out = ::testing::internal::GetCapturedStdout();
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(out, "");
  EXPECT_EQ(err, "");
  EXPECT_EQ(a.status, QualityStatus::kOk) << a.message;
  EXPECT_EQ(b.status, QualityStatus::kDegenerate);
  EXPECT_NE(b.message.find("qhull"), std::string::npos) << b.message;
  EXPECT_NE(c.status, QualityStatus::kOk);
  EXPECT_EQ(d.status, QualityStatus::kDegenerate) << d.message;
}

}  // namespace
}  // namespace taskmap
