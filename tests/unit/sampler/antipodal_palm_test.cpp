// The antipodal_palm sampler of parallel jaws whose palm must touch: every accepted pose has the
// palm's front on the surface (oracle: the plane through the palm-rigid points' front-most
// coordinate along the approach touches the surface within 20 µm, on a line along the approach
// through the pair, object behind it, free space in front), the pair at the pads'
// depth lies on the surface with its normals in the friction cones about the jaws' closing axis
// (the axis through the pads), the open fingers' points outside the object, determinism on any
// thread, and the fingertip variant (place_palm false) keeping the pads on the pair; on a jaw
// whose knuckles stand in front of its palm (tests/data/hands/knuckle_jaw) too; the
// construction-time probe that falls back fast where the jaws rarely span the object.
#include <cmath>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/sampler/sampler.hpp"

namespace taskmap {
namespace {

const HandModel& franka() {
  static const HandModel h =
      HandModel::load(std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/franka_hand.urdf");
  return h;
}
const ObjectModel& banana() {
  static const ObjectModel o =
      ObjectModel::load(std::string(TEST_DATA_DIR) + "/real/objects/ycb_011_banana.obj");
  return o;
}
const HandModel& knuckleJaw() {
  static const HandModel h =
      HandModel::load(std::string(TEST_DATA_DIR) + "/hands/knuckle_jaw/knuckle_jaw.urdf");
  return h;
}
const ObjectModel& soupCan() {
  static const ObjectModel o =
      ObjectModel::load(std::string(TEST_DATA_DIR) + "/meshes/soup_can.obj");
  return o;
}
const ObjectModel& ycbMug() {
  static const ObjectModel o =
      ObjectModel::load(std::string(TEST_DATA_DIR) + "/real/objects/ycb_025_mug.obj");
  return o;
}
const ObjectModel& cylinder() {
  static const ObjectModel o =
      ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/cylinder.obj");
  return o;
}

SamplerOptions palmOptions(const HandModel& h) {
  SamplerOptions o;
  o.kind = SamplerKind::kAntipodalPalm;
  o.approach_axis = h.approachAxis().normalized();
  o.jaws = jawGeometry(h);
  o.finger_points = fingerCheckPoints(h, 0.01);
  o.friction = 0.5;
  return o;
}

// Largest coordinate along the approach of the palm-rigid links' shape points at `pose`
// (object frame): box corners and hull points, as the sampler takes them.
double palmFrontAt(const HandModel& h, const Pose& pose, const Eigen::Vector3d& w) {
  const std::vector<Eigen::Isometry3d> poses = h.linkPoses(h.preshape());
  double front = -1e300;
  for (std::size_t l = 0; l < h.links().size(); ++l) {
    if (!h.links()[l].palm) continue;
    for (const CollisionShape& s : h.links()[l].shapes) {
      std::vector<Eigen::Vector3d> pts = s.points;
      if (s.type == ShapeType::kBox)
        for (int i = 0; i < 8; ++i)
          pts.push_back(0.5 * Eigen::Vector3d((i & 1) ? s.box_size.x() : -s.box_size.x(),
                                              (i & 2) ? s.box_size.y() : -s.box_size.y(),
                                              (i & 4) ? s.box_size.z() : -s.box_size.z()));
      for (const Eigen::Vector3d& p : pts) {
        const Eigen::Vector3d x = pose.position + pose.orientation * (poses[l] * (s.origin * p));
        front = std::max(front, w.dot(x));
      }
    }
  }
  return front;
}

TEST(AntipodalPalmTest, PalmFrontOnTheSurfaceAndPairInTheCones) {
  const double cos_cone = std::cos(std::atan(0.5));
  // The Franka hand on the banana and the cylinder; the knuckle hand (knuckles in front of its
  // palm, pads on distal links) on the soup-can-sized cylinder.
  const std::pair<const HandModel*, const ObjectModel*> cases[] = {
      {&franka(), &banana()}, {&franka(), &cylinder()}, {&knuckleJaw(), &soupCan()}};
  for (const auto& [hp, obj] : cases) {
    const HandModel& h = *hp;
    SCOPED_TRACE(obj->name() + " x " + h.name());
    const Sampler s(*obj, palmOptions(h));
    const JawGeometry& g = *s.options().jaws;
    const Eigen::Vector3d a = h.approachAxis().normalized();
    int accepted = 0;
    for (std::uint64_t t = 0; t < 100; ++t) {
      const std::optional<AntipodalPair> p = s.antipodalPair(5, t);
      if (!p) continue;
      ++accepted;
      const Pose pose = s.sample(5, t);
      const Eigen::Matrix3d r = pose.orientation.toRotationMatrix();
      const Eigen::Vector3d w = r * a, c = r * g.closing_axis;
      // The pair: on the surface, across the closing axis, in the friction cones.
      EXPECT_LT(obj->distanceToSurface(p->p1), 1e-9);
      EXPECT_LT(obj->distanceToSurface(p->p2), 1e-9);
      const Eigen::Vector3d u = (p->p2 - p->p1).normalized();
      EXPECT_NEAR(u.dot(c), 1.0, 1e-9);
      EXPECT_GE(-p->n1.dot(u), cos_cone - 1e-12);
      EXPECT_GE(p->n2.dot(u), cos_cone - 1e-12);
      const double width = (p->p2 - p->p1).norm();
      EXPECT_LE(width, g.open_width - 0.002 + 1e-12);
      // The pads' midpoint on the line through the pair's midpoint along the approach.
      const Eigen::Vector3d pads = pose.position + r * g.pad_midpoint;
      const Eigen::Vector3d off = pads - 0.5 * (p->p1 + p->p2);
      EXPECT_LT((off - off.dot(w) * w).norm(), 1e-9);
      // The palm's front: the plane w·x = front (the oracle takes the palm's points at the
      // pose) touches the surface at a point whose line along w crosses the pair's segment (the
      // surface point drawn): searched along the segment, outside just in front of the plane,
      // inside just behind it.
      const double front = palmFrontAt(h, pose, w);
      const double depth = a.dot(g.pad_midpoint) - g.palm_front;
      EXPECT_NEAR(w.dot(pads) - front, depth, 1e-9);
      bool touches = false;
      for (int k = 0; k <= 4000 && !touches; ++k) {
        const Eigen::Vector3d x = p->p1 + (k / 4000.0) * (p->p2 - p->p1);
        const Eigen::Vector3d y = x - (w.dot(x) - front) * w;
        touches = obj->distanceToSurface(y) < 2e-5 && !obj->contains(y - 1e-4 * w) &&
                  obj->contains(y + 1e-4 * w);
      }
      EXPECT_TRUE(touches) << "trial " << t;
      // No open finger point inside, nor within 1 mm of the surface (a finger grazing the
      // object would touch before the palm).
      for (const Eigen::Vector3d& q : s.options().finger_points) {
        ASSERT_FALSE(obj->contains(pose.position + r * q)) << "trial " << t;
        ASSERT_GE(obj->distanceToSurface(pose.position + r * q), 1e-3) << "trial " << t;
      }
    }
    EXPECT_GT(accepted, 60);
  }
}

TEST(AntipodalPalmTest, PosesArePureFunctionsOfSeedAndTrialOnAnyThread) {
  const Sampler s(banana(), palmOptions(franka()));
  std::vector<Pose> here(64), there(64);
  for (std::uint64_t t = 0; t < 64; ++t) here[t] = s.sample(9, 63 - t);
  std::thread th([&] {
    for (std::uint64_t t = 0; t < 64; ++t) there[t] = s.sample(9, 63 - t);
  });
  th.join();
  for (std::size_t i = 0; i < 64; ++i) {
    EXPECT_EQ(here[i].position, there[i].position);
    EXPECT_EQ(here[i].orientation.coeffs(), there[i].orientation.coeffs());
  }
  EXPECT_NE(s.sample(9, 1).position, s.sample(9, 2).position);
}

TEST(AntipodalPalmTest, ProbeFallsBackToMixedWhereTheJawsRarelySpanTheObject) {
  // The YCB mug (8.6 cm) is wider than the Franka opening (8 cm): the construction-time probe
  // finds too few poses for half the trials to find one within 16 attempts, so the sampler
  // makes no attempt and its trials are the mixed sampler's; on the banana and the soup can it
  // keeps the 16. The probe is the same for any seed and on any thread (its generators are its
  // own).
  const Sampler mug(ycbMug(), palmOptions(franka()));
  EXPECT_EQ(mug.attemptsInForce(), 0);
  EXPECT_EQ(Sampler(banana(), palmOptions(franka())).attemptsInForce(), 16);
  EXPECT_EQ(Sampler(soupCan(), palmOptions(knuckleJaw())).attemptsInForce(), 16);
  int other = 0;
  std::thread th([&] { other = Sampler(ycbMug(), palmOptions(franka())).attemptsInForce(); });
  th.join();
  EXPECT_EQ(other, 0);
  // The mixed sampler's poses, trial for trial (volume on even trials, surface on odd), and no
  // antipodal pair.
  SamplerOptions mixed = palmOptions(franka());
  mixed.kind = SamplerKind::kMixed;
  const Sampler as_mixed(ycbMug(), mixed);
  for (std::uint64_t t = 0; t < 50; ++t) {
    EXPECT_EQ(mug.kindOfTrial(t), t % 2 == 0 ? SamplerKind::kVolume : SamplerKind::kSurface);
    EXPECT_FALSE(mug.antipodalPair(4, t).has_value());
    EXPECT_EQ(mug.sample(4, t).position, as_mixed.sample(4, t).position);
    EXPECT_EQ(mug.sample(4, t).orientation.coeffs(), as_mixed.sample(4, t).orientation.coeffs());
  }
  // Where the probe keeps the attempts, trials are antipodal_palm's.
  EXPECT_EQ(Sampler(banana(), palmOptions(franka())).kindOfTrial(0), SamplerKind::kAntipodalPalm);
  // Other kinds keep their attempts.
  SamplerOptions o = palmOptions(franka());
  o.kind = SamplerKind::kAntipodal;
  EXPECT_EQ(Sampler(ycbMug(), o).attemptsInForce(), 16);
}

TEST(AntipodalPalmTest, FingertipVariantKeepsThePadsOnThePair) {
  SamplerOptions o = palmOptions(franka());
  o.place_palm = false;
  const Sampler s(banana(), o);
  const JawGeometry& g = *s.options().jaws;
  int accepted = 0;
  for (std::uint64_t t = 0; t < 40; ++t) {
    const std::optional<AntipodalPair> p = s.antipodalPair(2, t);
    if (!p) continue;
    ++accepted;
    const Pose pose = s.sample(2, t);
    const Eigen::Vector3d mid = pose.position + pose.orientation * g.pad_midpoint;
    EXPECT_LT((mid - 0.5 * (p->p1 + p->p2)).norm(), 1e-9);
    for (const Eigen::Vector3d& q : s.options().finger_points)
      ASSERT_GE(banana().distanceToSurface(pose.position + pose.orientation * q), 1e-3);
  }
  EXPECT_GT(accepted, 20);
}

TEST(AntipodalPalmTest, FallsBackToMixedWhereEveryPalmPoseGrazesTheObject) {
  // The bundled panda (8 cm opening, 4.5 cm fingers) with its palm on a sphere 8 cm across:
  // its fingers reach the sphere's equator, where the sphere is as wide as the opening, so at
  // every palm pose a finger grazes the surface and would touch before the palm (before the
  // 1 mm clearance every such trial of a build ended no_palm_contact). The probe finds no pose
  // and the trials are the mixed sampler's.
  const HandModel panda = HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/panda/panda.urdf");
  const ObjectModel sphere = ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/sphere.obj");
  const Sampler s(sphere, palmOptions(panda));
  EXPECT_EQ(s.attemptsInForce(), 0);
  EXPECT_EQ(s.kindOfTrial(1), SamplerKind::kSurface);
}

TEST(AntipodalPalmTest, DefaultKindIsAntipodalPalmForJawsMixedOtherwise) {
  const HandModel barrett =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  EXPECT_EQ(defaultSamplerKind(franka()), SamplerKind::kAntipodalPalm);
  EXPECT_EQ(defaultSamplerKind(knuckleJaw()), SamplerKind::kAntipodalPalm);
  EXPECT_EQ(defaultSamplerKind(barrett), SamplerKind::kMixed);
  // Unset kind: antipodal_palm when the jaws and finger points are given, else mixed; a kind
  // that is set is kept.
  SamplerOptions o = palmOptions(franka());
  o.kind.reset();
  EXPECT_EQ(samplerKindOf(o), SamplerKind::kAntipodalPalm);
  EXPECT_EQ(Sampler(banana(), o).kindOfTrial(0), SamplerKind::kAntipodalPalm);
  o.finger_points.clear();
  EXPECT_EQ(samplerKindOf(o), SamplerKind::kMixed);
  EXPECT_EQ(samplerKindOf(SamplerOptions{}), SamplerKind::kMixed);
  o.kind = SamplerKind::kVolume;
  EXPECT_EQ(samplerKindOf(o), SamplerKind::kVolume);
}

TEST(AntipodalPalmTest, NeedsJawsAndFingerPoints) {
  SamplerOptions o = palmOptions(franka());
  o.finger_points.clear();
  EXPECT_TRUE(testing::throwsError([&] { Sampler(banana(), o); },
                                   {"antipodal_palm sampler needs a parallel-jaw", "--sampler"}));
  o = palmOptions(franka());
  o.jaws.reset();
  EXPECT_TRUE(testing::throwsError([&] { Sampler(banana(), o); },
                                   {"antipodal_palm sampler needs a parallel-jaw", "--sampler"}));
  EXPECT_EQ(samplerKindFromString("antipodal_palm"), SamplerKind::kAntipodalPalm);
  EXPECT_STREQ(toString(SamplerKind::kAntipodalPalm), "antipodal_palm");
  EXPECT_TRUE(
      testing::throwsError([&] { fingerCheckPoints(franka(), 0.0); }, {"positive spacing"}));
}

TEST(AntipodalPalmTest, FingerCheckPointsCoverBoxFacesAtTheSpacing) {
  // The barrett's fingers are boxes: the dense points include every vertex (openFingerPoints)
  // and add a grid on the faces.
  const HandModel barrett =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  const std::vector<Eigen::Vector3d> sparse = openFingerPoints(barrett);
  const std::vector<Eigen::Vector3d> dense = fingerCheckPoints(barrett, 0.01);
  EXPECT_GT(dense.size(), 3 * sparse.size());
  for (const Eigen::Vector3d& v : sparse) {
    double best = 1e300;
    for (const Eigen::Vector3d& d : dense) best = std::min(best, (d - v).norm());
    EXPECT_LT(best, 1e-12);
  }
}

}  // namespace
}  // namespace taskmap
