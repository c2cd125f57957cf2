// Antipodal sampling for parallel jaws: the jaws' pads from the hand model, every accepted pair
// checked against a brute-force oracle (both contacts on the surface, the segment's first exit,
// normals in the friction cones, width within the opening), the palm pose that puts the pads on
// the pair, and determinism (a pure function of seed and trial, the same from any thread). The
// enclose sampler of multi-finger hands: palm on the surface, no open finger point inside.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/sampler/sampler.hpp"

namespace taskmap {
namespace {

HandModel hand(const std::string& path) {
  return HandModel::load(path);
}
std::string bundled(const std::string& name) {
  return std::string(TASKMAP_HANDS_DIR) + "/" + name + "/" + name + ".urdf";
}
std::string testHand(const std::string& name) {
  return std::string(TEST_DATA_DIR) + "/hands/" + name + "/" + name + ".urdf";
}
std::string realHand() {
  return std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/franka_hand.urdf";
}
const ObjectModel& banana() {
  static const ObjectModel o =
      ObjectModel::load(std::string(TEST_DATA_DIR) + "/real/objects/ycb_011_banana.obj");
  return o;
}
const ObjectModel& mug() {
  static const ObjectModel o = ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/mug.obj");
  return o;
}

SamplerOptions jawOptions(const HandModel& h) {
  SamplerOptions o;
  o.kind = SamplerKind::kAntipodal;
  o.approach_axis = h.approachAxis().normalized();
  o.jaws = jawGeometry(h);
  o.friction = 0.5;
  return o;
}

TEST(AntipodalTest, JawGeometryOfTheParallelGrippers) {
  // Panda and the real Franka hand: fingers 4 cm each side open (8 cm), closed to touching;
  // the fingers move along the palm's y axis. The Robotiq-style hand: 85 mm stroke.
  for (const std::string& path : {bundled("panda"), realHand()}) {
    SCOPED_TRACE(path);
    const std::optional<JawGeometry> g = jawGeometry(hand(path));
    ASSERT_TRUE(g.has_value());
    EXPECT_NEAR(g->open_width, 0.08, 0.005);
    EXPECT_LT(g->closed_width, 0.005);
    EXPECT_NEAR(std::abs(g->closing_axis.y()), 1.0, 1e-6);
    // The pads lie ahead of the palm along the approach axis, between the fingers.
    EXPECT_GT(g->pad_midpoint.z(), 0.0);
    EXPECT_LT(std::abs(g->pad_midpoint.y()), 1e-3);
  }
  const std::optional<JawGeometry> r = jawGeometry(hand(testHand("robotiq_2f85_style")));
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(r->open_width, 0.085, 0.01);
  EXPECT_GT(r->pad_midpoint.z(), 0.0);
  // Knuckles in front of the palm (tests/data/hands/knuckle_jaw): the pads are on each finger's
  // distal body. From the URDF: pad centre 0.032 + 0.04 sin 20° - 0.004 m off centre, inner
  // face 0.004 m further in; pad centre 0.05 + 0.04 cos 20° + 0.02 m above the base, the palm
  // frame 0.06 m up. The knuckles' inner edges (0.056 m apart) are not the opening.
  const std::optional<JawGeometry> k = jawGeometry(hand(testHand("knuckle_jaw")));
  ASSERT_TRUE(k.has_value());
  const double face = 0.032 + 0.04 * std::sin(20.0 * M_PI / 180.0) - 0.008;
  EXPECT_NEAR(k->open_width, 2.0 * face, 1e-6);
  EXPECT_NEAR(std::abs(k->closing_axis.x()), 1.0, 1e-9);
  EXPECT_NEAR(k->pad_midpoint.z(), 0.05 + 0.04 * std::cos(20.0 * M_PI / 180.0) + 0.02 - 0.06, 1e-6);
  EXPECT_NEAR(k->palm_front, 0.0, 1e-12);
  // Three or five fingers are not jaws.
  EXPECT_FALSE(jawGeometry(hand(bundled("barrett"))).has_value());
  EXPECT_FALSE(jawGeometry(hand(bundled("humanoid"))).has_value());
}

TEST(AntipodalTest, AntipodalNeedsJawsAndValidOptions) {
  SamplerOptions o;
  o.kind = SamplerKind::kAntipodal;
  EXPECT_TRUE(testing::throwsError([&] { Sampler(mug(), o); }, {"parallel-jaw hand", "--sampler"}));
  EXPECT_EQ(samplerKindFromString("antipodal"), SamplerKind::kAntipodal);
  EXPECT_STREQ(toString(SamplerKind::kAntipodal), "antipodal");
  o = jawOptions(hand(bundled("panda")));
  o.friction = -0.1;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"friction"}));
  o = jawOptions(hand(bundled("panda")));
  o.attempts = 0;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"attempts"}));
  o = jawOptions(hand(bundled("panda")));
  o.jaws->open_width = 0.0;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"open_width"}));
}

/// Oracle: the first point where the segment p1 + t u leaves the solid, found by marching the
/// inside test in steps of 0.1 mm and bisecting (independent of the ray query).
double firstExitByMarching(const ObjectModel& obj, const Eigen::Vector3d& p1,
                           const Eigen::Vector3d& u, double length) {
  const double step = 1e-4;
  double t = 2e-5;
  if (!obj.contains(p1 + t * u)) return 0.0;
  while (t < length + step && obj.contains(p1 + (t + step) * u)) t += step;
  double lo = t, hi = t + step;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (obj.contains(p1 + mid * u) ? lo : hi) = mid;
  }
  return hi;
}

TEST(AntipodalTest, AcceptedPairsSatisfyTheOracle) {
  const HandModel panda = hand(bundled("panda"));
  const double cos_cone = std::cos(std::atan(0.5));
  for (const ObjectModel* obj : {&banana(), &mug()}) {
    SCOPED_TRACE(obj->name());
    const Sampler s(*obj, jawOptions(panda));
    const JawGeometry& g = *s.options().jaws;
    int accepted = 0;
    for (std::uint64_t t = 0; t < 200; ++t) {
      const std::optional<AntipodalPair> p = s.antipodalPair(4, t);
      if (!p) continue;
      ++accepted;
      const Eigen::Vector3d axis = p->p2 - p->p1;
      const double w = axis.norm();
      const Eigen::Vector3d u = axis / w;
      EXPECT_LT(obj->distanceToSurface(p->p1), 1e-9);
      EXPECT_LT(obj->distanceToSurface(p->p2), 1e-9);
      EXPECT_GE(w, std::max(g.closed_width, 0.0) + 0.002 - 1e-12);
      EXPECT_LE(w, g.open_width - 0.002 + 1e-12);
      // In the cones: the angle between each normal and the axis within atan(mu).
      EXPECT_GE(-p->n1.dot(u), cos_cone - 1e-12);
      EXPECT_GE(p->n2.dot(u), cos_cone - 1e-12);
      // p2 is where the segment first leaves the solid.
      EXPECT_NEAR(firstExitByMarching(*obj, p->p1, u, w), w, 2e-6) << "trial " << t;
    }
    // Most trials find a pair within their attempts on these objects.
    EXPECT_GT(accepted, 150);
  }
}

TEST(AntipodalTest, PalmPosePutsThePadsOnThePair) {
  for (const std::string& path : {bundled("panda"), realHand(), testHand("robotiq_2f85_style")}) {
    SCOPED_TRACE(path);
    const HandModel h = hand(path);
    const Sampler s(banana(), jawOptions(h));
    const JawGeometry& g = *s.options().jaws;
    const Eigen::Vector3d a = h.approachAxis().normalized();
    for (std::uint64_t t = 0; t < 50; ++t) {
      const std::optional<AntipodalPair> p = s.antipodalPair(2, t);
      if (!p) continue;
      const Pose pose = s.sample(2, t);
      const Eigen::Matrix3d r = pose.orientation.toRotationMatrix();
      const Eigen::Vector3d mid = pose.position + r * g.pad_midpoint;
      EXPECT_LT((mid - 0.5 * (p->p1 + p->p2)).norm(), 1e-9);
      const Eigen::Vector3d u = (p->p2 - p->p1).normalized();
      EXPECT_NEAR((r * g.closing_axis).dot(u), 1.0, 1e-9);
      EXPECT_NEAR((r * a).dot(u), 0.0, 1e-9);
    }
  }
}

TEST(AntipodalTest, ApproachIsUniformAboutTheJawAxis) {
  // The approach direction's angle about the pair's axis is uniform: its cosine and sine
  // against a frame fixed to the axis average 0 (std of the mean ~ 0.71 / sqrt(n)).
  const HandModel h = hand(bundled("panda"));
  const Sampler s(mug(), jawOptions(h));
  double c = 0, sn = 0;
  int n = 0;
  for (std::uint64_t t = 0; t < 2000; ++t) {
    const std::optional<AntipodalPair> p = s.antipodalPair(8, t);
    if (!p) continue;
    const Eigen::Vector3d u = (p->p2 - p->p1).normalized();
    const Eigen::Vector3d e1 = u.unitOrthogonal(), e2 = u.cross(e1);
    const Eigen::Vector3d w = s.sample(8, t).orientation * h.approachAxis().normalized();
    c += w.dot(e1);
    sn += w.dot(e2);
    ++n;
  }
  ASSERT_GT(n, 1000);
  EXPECT_LT(std::abs(c / n), 5 * 0.71 / std::sqrt(n));
  EXPECT_LT(std::abs(sn / n), 5 * 0.71 / std::sqrt(n));
}

TEST(AntipodalTest, PosesArePureFunctionsOfSeedAndTrialOnAnyThread) {
  const HandModel h = hand(realHand());
  const Sampler a(banana(), jawOptions(h)), b(banana(), jawOptions(h));
  const int n = 400;
  std::vector<Eigen::Matrix<double, 7, 1>> forward(n);
  for (int t = 0; t < n; ++t) forward[t] = a.sample(3, static_cast<std::uint64_t>(t)).toVector7();
  // Four threads, interleaved indices, in reverse order, on another instance.
  std::vector<Eigen::Matrix<double, 7, 1>> threaded(n);
  std::vector<std::thread> workers;
  for (int k = 0; k < 4; ++k)
    workers.emplace_back([&, k] {
      for (int t = n - 1 - k; t >= 0; t -= 4)
        threaded[t] = b.sample(3, static_cast<std::uint64_t>(t)).toVector7();
    });
  for (std::thread& w : workers) w.join();
  for (int t = 0; t < n; ++t) EXPECT_EQ(threaded[t], forward[t]) << t;
  int same_other_seed = 0;
  for (int t = 0; t < n; ++t)
    same_other_seed += a.sample(4, static_cast<std::uint64_t>(t)).toVector7() == forward[t];
  EXPECT_EQ(same_other_seed, 0);
}

TEST(AntipodalTest, FallsBackToTheSurfaceSamplerWhenNoPairFits) {
  // Jaws narrower than any width of the box: every attempt fails, every trial is a surface pose.
  const HandModel h = hand(bundled("panda"));
  SamplerOptions o = jawOptions(h);
  o.jaws->open_width = 0.003;
  o.jaws->closed_width = 0.0;
  const Sampler s(mug(), o);
  SamplerOptions so = o;
  so.kind = SamplerKind::kSurface;
  for (std::uint64_t t = 0; t < 20; ++t) {
    EXPECT_FALSE(s.antipodalPair(1, t).has_value());
    const Pose p = s.sample(1, t);
    EXPECT_TRUE(p.position.allFinite());
    EXPECT_NEAR(p.orientation.norm(), 1.0, 1e-12);
  }
}

TEST(EncloseTest, AcceptedPosesKeepTheOpenFingersOutside) {
  const HandModel barrett = hand(bundled("barrett"));
  SamplerOptions o;
  o.kind = SamplerKind::kEnclose;
  o.approach_axis = barrett.approachAxis().normalized();
  o.finger_points = openFingerPoints(barrett);
  ASSERT_GT(o.finger_points.size(), 20u);
  const Sampler s(mug(), o);
  int enclosing = 0;
  for (std::uint64_t t = 0; t < 200; ++t) {
    const Pose p = s.sample(6, t);
    EXPECT_EQ(s.sample(6, t).toVector7(), p.toVector7());
    // The palm's approach axis points into the object along a face normal, the palm origin on
    // the surface.
    const Eigen::Matrix3d r = p.orientation.toRotationMatrix();
    bool inside = false;
    for (const Eigen::Vector3d& q : o.finger_points) inside |= mug().contains(p.position + r * q);
    if (inside) continue;  // a fallback pose
    ++enclosing;
    EXPECT_LT(mug().distanceToSurface(p.position), 1e-9);
  }
  // The mug's handle and rim leave many poses whose fingers clear the object.
  EXPECT_GT(enclosing, 100);
  o.finger_points.clear();
  EXPECT_TRUE(testing::throwsError([&] { Sampler(mug(), o); }, {"enclose sampler", "--sampler"}));
  EXPECT_EQ(samplerKindFromString("enclose"), SamplerKind::kEnclose);
}

}  // namespace
}  // namespace taskmap
