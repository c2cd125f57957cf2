// Per-link contact reduction (reduceContactsPerLink, QualityOptions::contacts_per_link) and the
// force-closure pre-test (hullMissesOrigin, QualityOptions::closure_pretest): at most K contacts
// per link, the deepest kept, exact pass-through below K, a subset hull on flat faces, and the
// pre-test's verdicts against qhull on random and on real (YCB mug) contact sets.
#include "taskmap/quality/contact_reduction.hpp"

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "quality_fixtures.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/quality/grasp_quality.hpp"
#include "taskmap/quality/wrench_epsilon.hpp"

namespace taskmap {
namespace {

/// A patch of n contacts of one link about `centre` on a curved surface (normals spread by
/// `tilt`), deepest not first, some without pressure.
std::vector<Contact> patch(Rng& rng, int link, int n, const Eigen::Vector3d& centre, double tilt) {
  std::vector<Contact> out;
  const Eigen::Vector3d axis = centre.normalized();
  for (int i = 0; i < n; ++i) {
    Contact c;
    c.point = centre + 0.01 * rng.direction();
    c.normal = (axis + tilt * rng.direction()).normalized();
    c.depth = i % 5 == 4 ? 0.0 : rng.uniform(1e-4, 2e-3);
    c.link = link;
    out.push_back(c);
  }
  return out;
}

std::vector<Contact> manyLinkPatches(Rng& rng, double tilt) {
  std::vector<Contact> all;
  const Eigen::Vector3d centres[] = {{0.05, 0, 0}, {-0.05, 0, 0}, {0, 0.03, 0}, {0, 0, -0.02}};
  for (int l = 0; l < 4; ++l) {
    const auto p = patch(rng, l, 2 + static_cast<int>(rng.below(12)), centres[l], tilt);
    all.insert(all.end(), p.begin(), p.end());
  }
  return all;
}

/// Real contact sets: the humanoid hand on the YCB mug scan (tests/data/quality).
struct RecordedGrasps {
  Eigen::Vector3d com;
  double torque_scale = 0.0;
  std::vector<std::vector<Contact>> grasps;
};

RecordedGrasps readRecorded(const std::string& name) {
  const std::string path = std::string(TEST_DATA_DIR) + "/quality/" + name;
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  std::stringstream body;
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') body << line << '\n';
  RecordedGrasps r;
  body >> r.com.x() >> r.com.y() >> r.com.z() >> r.torque_scale;
  int n = 0;
  while (body >> n) {
    std::vector<Contact> g(static_cast<std::size_t>(n));
    for (Contact& c : g)
      body >> c.point.x() >> c.point.y() >> c.point.z() >> c.normal.x() >> c.normal.y() >>
          c.normal.z() >> c.depth >> c.link;
    r.grasps.push_back(std::move(g));
  }
  return r;
}

TEST(ContactReductionTest, AtMostKPerLinkAndTheDeepestOfEachLinkKept) {
  for (int s = 0; s < 50; ++s) {
    Rng rng(33, static_cast<std::uint64_t>(s));
    const auto contacts = manyLinkPatches(rng, 0.3);
    for (int k = 1; k <= 4; ++k) {
      const auto reduced = reduceContactsPerLink(contacts, k);
      std::map<int, int> count;
      std::map<int, double> deepest_in, deepest_out;
      std::map<int, Eigen::Vector3d> deepest_point;
      for (const Contact& c : contacts)
        if (c.depth > deepest_in[c.link]) {
          deepest_in[c.link] = c.depth;
          deepest_point[c.link] = c.point;
        }
      bool has_deepest[4] = {false, false, false, false};
      for (const Contact& c : reduced) {
        ++count[c.link];
        EXPECT_GT(c.depth, 0.0);
        EXPECT_NEAR(c.normal.norm(), 1.0, 1e-12);
        if (c.point == deepest_point[c.link]) has_deepest[c.link] = true;
        deepest_out[c.link] = std::max(deepest_out[c.link], c.depth);
      }
      for (const auto& [link, n] : count) {
        EXPECT_LE(n, k) << "set " << s << " link " << link;
        EXPECT_TRUE(has_deepest[link]) << "set " << s << " link " << link;
        EXPECT_EQ(deepest_out[link], deepest_in[link]);
      }
      EXPECT_EQ(count.size(), deepest_in.size());  // every pressed link is still there
    }
  }
}

TEST(ContactReductionTest, LinksWithAtMostKContactsPassUnchangedAndUnknownLinksAreNotGrouped) {
  Rng rng(34, 1);
  auto contacts = testing::randomContacts(rng, 6, 0.2);  // one contact per link
  Contact unknown = contacts[0];
  unknown.link = -1;
  contacts.push_back(unknown);
  contacts.push_back(unknown);
  const auto reduced = reduceContactsPerLink(contacts, 1);
  ASSERT_EQ(reduced.size(), contacts.size());
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    EXPECT_EQ(reduced[i].point, contacts[i].point);
    EXPECT_EQ(reduced[i].normal, contacts[i].normal);
    EXPECT_EQ(reduced[i].depth, contacts[i].depth);
  }
  // So the quality is bit for bit the one without reduction.
  QualityOptions o;
  o.contacts_per_link = 1;
  const QualityResult a = evaluateGrasp(contacts, Eigen::Vector3d::Zero(), 0.05);
  const QualityResult b = evaluateGrasp(contacts, Eigen::Vector3d::Zero(), 0.05, o);
  EXPECT_EQ(a.force_closure, b.force_closure);
  EXPECT_EQ(a.epsilon, b.epsilon);
  EXPECT_EQ(a.volume, b.volume);
}

TEST(ContactReductionTest, RepresentativeTakesItsGroupsMeanNormalAndLargestDepth) {
  // One link, K = 2: the deepest (b), then the farthest from it (c); a is nearest to b.
  Contact a, b, c;
  a.point = {0, 0, 0};
  a.normal = Eigen::Vector3d(1, 0, 0);
  a.depth = 2e-3;
  b.point = {0, 0.001, 0};
  b.normal = Eigen::Vector3d(0, 1, 0);
  b.depth = 3e-3;
  c.point = {0, 0.02, 0};
  c.normal = Eigen::Vector3d(0, 0, 1);
  c.depth = 1e-3;
  for (Contact* x : {&a, &b, &c}) x->link = 7;
  const auto r = reduceContactsPerLink({a, b, c}, 2);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].point, b.point);
  EXPECT_TRUE(r[0].normal.isApprox(Eigen::Vector3d(1, 1, 0).normalized(), 1e-15));
  EXPECT_EQ(r[0].depth, 3e-3);
  EXPECT_EQ(r[1].point, c.point);
  EXPECT_EQ(r[1].normal, c.normal);
}

TEST(ContactReductionTest, OnFlatFacesTheReducedHullLiesInsideTheFullOne) {
  // Every contact of a link on one face shares its normal, so the representatives are a subset
  // of the contacts: the reduced wrench set is a subset, its hull inside the full one. Epsilon
  // can only shrink and force closure only be lost.
  int compared = 0;
  for (int s = 0; s < 80; ++s) {
    Rng rng(35, static_cast<std::uint64_t>(s));
    std::vector<Contact> contacts;
    const Eigen::Vector3d half(0.05, 0.03, 0.02);
    for (int l = 0; l < 3 + s % 3; ++l) {
      const int axis = static_cast<int>(rng.below(3));
      const double sign = rng.uniform() < 0.5 ? -1.0 : 1.0;
      for (int k = 0; k < 2 + static_cast<int>(rng.below(7)); ++k) {
        Contact c;
        for (int i = 0; i < 3; ++i) c.point(i) = rng.uniform(-half(i), half(i));
        c.point(axis) = sign * half(axis);
        c.normal = sign * Eigen::Vector3d::Unit(axis);
        c.depth = rng.uniform(1e-4, 1e-3);
        c.link = l;
        contacts.push_back(c);
      }
    }
    QualityOptions lean;
    lean.volume = VolumeMode::kNever;
    const QualityResult full = evaluateGrasp(contacts, Eigen::Vector3d::Zero(), 0.06, lean);
    if (full.status != QualityStatus::kOk) continue;
    for (int k : {1, 2, 3}) {
      QualityOptions o = lean;
      o.contacts_per_link = k;
      const QualityResult red = evaluateGrasp(contacts, Eigen::Vector3d::Zero(), 0.06, o);
      EXPECT_LE(red.epsilon, full.epsilon * (1 + 1e-9) + 1e-15) << "set " << s << " K " << k;
      if (red.force_closure) {
        EXPECT_TRUE(full.force_closure) << "set " << s << " K " << k;
      }
      EXPECT_LE(red.contacts_used, full.contacts_used);
      ++compared;
    }
  }
  EXPECT_GT(compared, 150);
}

TEST(ContactReductionTest, BadCountsAreRefusedWithTheOptionsName) {
  try {
    reduceContactsPerLink({}, 0);
    FAIL() << "per_link 0 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("contacts_per_link"), std::string::npos) << e.what();
  }
  QualityOptions o;
  o.contacts_per_link = -1;
  EXPECT_THROW(o.validate(), Error);
}

TEST(ContactReductionTest, ReductionOnRealScanContactsKeepsAtMostKAndIsDeterministic) {
  const RecordedGrasps r = readRecorded("ycb_mug_humanoid_contacts.txt");
  ASSERT_EQ(r.grasps.size(), 48u);
  for (const auto& g : r.grasps) {
    const auto a = reduceContactsPerLink(g, 2), b = reduceContactsPerLink(g, 2);
    ASSERT_EQ(a.size(), b.size());
    std::map<int, int> count;
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].point, b[i].point);
      EXPECT_EQ(a[i].normal, b[i].normal);
      ++count[a[i].link];
    }
    for (const auto& [link, n] : count) EXPECT_LE(n, 2);
  }
}

/// The pre-test against qhull on the same wrenches: a set it rejects is not force closure, and
/// evaluateGrasp with the pre-test gives the same verdict and epsilon as without.
void expectPretestAgrees(const std::vector<Contact>& contacts, const Eigen::Vector3d& com, double r,
                         const std::string& what, int* rejected, int* closures) {
  const WrenchMatrix w = contactWrenches(contacts, com, r);
  WrenchHull hull = wrenchHull(w);
  QualityResult q;
  summarizeHull(hull, q);
  if (q.status != QualityStatus::kOk) return;
  const bool misses = hullMissesOrigin(w, w.colwise().norm().maxCoeff());
  if (misses) {
    EXPECT_FALSE(q.force_closure) << what;
  }
  if (q.force_closure) {
    EXPECT_FALSE(misses) << what;
  }
  *rejected += misses;
  *closures += q.force_closure;
  QualityOptions plain, pre;
  plain.volume = pre.volume = VolumeMode::kNever;
  pre.closure_pretest = true;
  const QualityResult a = evaluateGrasp(contacts, com, r, plain);
  const QualityResult b = evaluateGrasp(contacts, com, r, pre);
  EXPECT_EQ(a.force_closure, b.force_closure) << what;
  EXPECT_EQ(a.epsilon, b.epsilon) << what;
  EXPECT_EQ(a.force_closure, q.force_closure) << what;
}

TEST(ContactReductionTest, ClosurePretestAgreesWithQhullOnRandomSets) {
  int rejected = 0, closures = 0;
  for (int n : {3, 4, 6, 8}) {
    for (int s = 0; s < 24; ++s) {
      Rng rng(36, static_cast<std::uint64_t>(100 * n + s));
      auto contacts = testing::randomContacts(rng, n, s % 2 ? 0.4 : 0.0);
      // Half the sets on one side of the object: the origin outside their hull.
      if (s % 4 < 2)
        for (Contact& c : contacts) {
          c.point.x() = std::abs(c.point.x());
          c.normal.x() = std::abs(c.normal.x());
          c.normal.normalize();
        }
      expectPretestAgrees(contacts, Eigen::Vector3d(0.002, 0, -0.001), 0.05,
                          std::to_string(n) + " contacts, set " + std::to_string(s), &rejected,
                          &closures);
    }
  }
  EXPECT_GT(rejected, 20);  // the pre-test does reject, and
  EXPECT_GT(closures, 10);  // never a force-closure set
}

TEST(ContactReductionTest, ClosurePretestAgreesWithQhullOnRealScanContacts) {
  const RecordedGrasps r = readRecorded("ycb_mug_humanoid_contacts.txt");
  int rejected = 0, closures = 0;
  // qhull's whole hull of ~150 wrenches costs ~0.1 s: every third grasp (16 of 48).
  for (std::size_t i = 0; i < r.grasps.size(); i += 3)
    expectPretestAgrees(r.grasps[i], r.com, r.torque_scale, "YCB mug grasp " + std::to_string(i),
                        &rejected, &closures);
  EXPECT_GT(closures, 5);
  EXPECT_GT(rejected, 0);
}

}  // namespace
}  // namespace taskmap
