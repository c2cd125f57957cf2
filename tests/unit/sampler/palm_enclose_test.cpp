// The palm_enclose sampler of multi-finger hands (real Allegro hand of tests/data/real, the
// bundled barrett): the hand geometry from its shapes (closing axis across the approach, palm
// front = the palm points' front-most coordinate), and on the reference box (6 x 8 x 12 cm,
// axis-aligned) an oracle for every accepted pose: the approach along a face's inward normal,
// the palm's front in that face's plane, the closing axis along the narrowest box extent across
// the approach (within the candidate spacing pi / kEncloseRolls / 2), the open fingers outside;
// then determinism on another thread and the option errors.
#include <algorithm>
#include <cmath>
#include <optional>
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

const HandModel& allegro() {
  static const HandModel h = HandModel::load(
      std::string(TEST_DATA_DIR) + "/real/hands/allegro_right/allegro_hand_description_right.urdf");
  return h;
}
const HandModel& barrett() {
  static const HandModel h =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  return h;
}
const ObjectModel& box() {
  static const ObjectModel o = ObjectModel::load(std::string(TASKMAP_OBJECTS_DIR) + "/box.obj");
  return o;
}

SamplerOptions encloseOptions(const HandModel& h) {
  SamplerOptions o;
  o.kind = SamplerKind::kPalmEnclose;
  o.approach_axis = h.approachAxis().normalized();
  o.enclose = encloseGeometry(h);
  o.finger_points = fingerCheckPoints(h, 0.01);
  return o;
}

TEST(PalmEnclose, GeometryFromTheHandsShapes) {
  for (const HandModel* h : {&allegro(), &barrett()}) {
    SCOPED_TRACE(h->name());
    const std::optional<EncloseGeometry> g = encloseGeometry(*h);
    ASSERT_TRUE(g);
    EXPECT_NO_THROW(g->validate());
    const Eigen::Vector3d a = h->approachAxis().normalized();
    EXPECT_NEAR(g->closing_axis.norm(), 1.0, 1e-9);
    EXPECT_NEAR(g->closing_axis.dot(a), 0.0, 1e-9);
    // Oracle for the palm's front: the largest approach coordinate of the palm points.
    double front = -1e300;
    for (const Eigen::Vector3d& p : palmShapePoints(*h, h->preshape()))
      front = std::max(front, a.dot(p));
    EXPECT_DOUBLE_EQ(g->palm_front, front);
    // The fingers' span along the closing axis holds every open finger point.
    for (const auto& finger : fingerShapePoints(*h, h->preshape()))
      for (const Eigen::Vector3d& p : finger) {
        EXPECT_GE(g->closing_axis.dot(p), g->span_min - 1e-12);
        EXPECT_LE(g->closing_axis.dot(p), g->span_max + 1e-12);
      }
    EXPECT_GT(g->span_max - g->span_min, 0.05);  // both hands open wider than 5 cm
    // The minimum part depth: half the thinnest finger link (the barrett's 2 cm boxes: 1 cm).
    double thin = 1e300;
    for (const HandLink& link : h->links())
      if (link.finger >= 0)
        for (const CollisionShape& shape : link.shapes) thin = std::min(thin, shape.thickness());
    EXPECT_DOUBLE_EQ(g->min_depth, 0.5 * thin);
  }
  EXPECT_DOUBLE_EQ(encloseGeometry(barrett())->min_depth, 0.01);
}

// The box's chord along the line y0 + s d (slab method, independent of the mesh's rays): the
// interval of s inside [lo, hi]; empty (first > second) when the line misses it.
std::pair<double, double> boxChord(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                   const Eigen::Vector3d& y0, const Eigen::Vector3d& d) {
  double s0 = -1e300, s1 = 1e300;
  for (int j = 0; j < 3; ++j) {
    if (std::abs(d[j]) < 1e-12) {
      if (y0[j] < lo[j] || y0[j] > hi[j]) return {1.0, 0.0};
      continue;
    }
    const double a = (lo[j] - y0[j]) / d[j], b = (hi[j] - y0[j]) / d[j];
    s0 = std::max(s0, std::min(a, b));
    s1 = std::min(s1, std::max(a, b));
  }
  return {s0, s1};
}

// Oracle on the axis-aligned box (6 x 8 x 12 cm): every accepted pose has its approach w along
// a face's inward normal and the palm's front in that face's plane; the chord the fingers close
// on (the box's chord along the closing axis c through the probe point: the palm's grasp centre
// across c, the probe depth along w, computed by slabs) is centred on the grasp centre clamped
// into the fingers' span and fits it; and the closing axis lies across the narrowest extent: its
// chord is at most that extent / cos(pi / 2 kEncloseRolls) (the candidates are pi / kEncloseRolls
// apart; a corner cut shorter counts too) for at least 90 % of the poses (a wider one is taken
// when the narrower direction's fingers would enter).
/// Distance from p to the axis-aligned box [lo, hi] when p is outside it, 0 inside.
double outsideDistance(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                       const Eigen::Vector3d& p) {
  return (p.cwiseMax(lo).cwiseMin(hi) - p).norm();
}

/// The oracle above for every pose drawn on `object`, whose outer surface is the box [lo, hi]
/// (the box itself, or a hollow box: the extent is the outer box's through the cavity). Returns
/// {accepted, narrow}.
std::pair<int, int> checkBoxPoses(const ObjectModel& object, const HandModel& h,
                                  const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const SamplerOptions o = encloseOptions(h);
  const EncloseGeometry& g = *o.enclose;
  const double m = o.enclose_margin, span = g.span_max - g.span_min - 2.0 * m;
  int accepted = 0, narrow = 0;
  for (std::uint64_t i = 0; i < 200; ++i) {
    Rng rng(7, i);
    const std::optional<Pose> pose =
        drawPalmEnclose(object, g, o.approach_axis, o.finger_points, 1, m, rng);
    if (!pose) continue;
    ++accepted;
    const Eigen::Matrix3d r = pose->orientation.toRotationMatrix();
    const Eigen::Vector3d w = r * o.approach_axis, c = r * g.closing_axis, v = c.cross(w);
    int k = 0;
    w.cwiseAbs().maxCoeff(&k);
    EXPECT_NEAR(std::abs(w[k]), 1.0, 1e-9) << "approach not along a face normal";
    // The face the palm is on: w points into the box, so the face is at hi[k] when w[k] < 0.
    const double face = w[k] < 0 ? hi[k] : lo[k];
    EXPECT_NEAR(w.dot(pose->position) + g.palm_front, w[k] * face, 1e-6)
        << "the palm's front is not in the face plane";
    EXPECT_NEAR(c.dot(w), 0.0, 1e-9);
    const double depth = std::min(g.probe_depth, 0.5 * (hi[k] - lo[k]));
    const Eigen::Vector3d y0 = pose->position + (g.palm_front + depth) * w + g.grasp_centre.y() * v;
    const auto [s0, s1] = boxChord(lo, hi, y0, c);
    EXPECT_LT(s0, s1) << "the closing line misses the box";
    const double width = s1 - s0;
    EXPECT_LE(width, span + 1e-6);
    const double centre =
        std::clamp(g.grasp_centre.x(), g.span_min + m + 0.5 * width, g.span_max - m - 0.5 * width);
    EXPECT_NEAR(0.5 * (s0 + s1), centre, 1e-6) << "chord not centred on the grasp centre";
    double narrowest = 1e300;
    for (int j = 0; j < 3; ++j)
      if (j != k) narrowest = std::min(narrowest, hi[j] - lo[j]);
    if (width <= narrowest / std::cos(M_PI / kEncloseRolls / 2.0) + 1e-6) ++narrow;
    // Every open finger point outside the box and at least the clearance (0.5 mm) off it.
    for (const Eigen::Vector3d& p : o.finger_points)
      EXPECT_GE(outsideDistance(lo, hi, pose->position + r * p), 5e-4) << "finger on the box";
  }
  return {accepted, narrow};
}

TEST(PalmEnclose, PalmOnTheFaceFingersAcrossTheNarrowExtent) {
  const Eigen::Vector3d lo(-0.03, -0.04, 0.0), hi(0.03, 0.04, 0.12);
  for (const HandModel* h : {&allegro(), &barrett()}) {
    SCOPED_TRACE(h->name());
    const auto [accepted, narrow] = checkBoxPoses(box(), *h, lo, hi);
    EXPECT_GT(accepted, 20);
    // At least 85 %: a wider direction is taken when the narrower one's fingers would enter the
    // box or lie on it (the barrett: 85 of 96).
    EXPECT_GE(narrow, accepted * 85 / 100) << narrow << " of " << accepted;
  }
}

/// The box [lo, hi] with a closed cavity `wall` metres inside each face (inner shell inward).
TriangleMesh hollowBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double wall) {
  TriangleMesh mesh;
  const auto shell = [&mesh](const Eigen::Vector3d& a, const Eigen::Vector3d& b, bool outward) {
    const int base = static_cast<int>(mesh.vertices.size());
    for (int i = 0; i < 8; ++i)
      mesh.vertices.emplace_back(i & 1 ? b.x() : a.x(), i & 2 ? b.y() : a.y(),
                                 i & 4 ? b.z() : a.z());
    const int quads[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                             {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
    const Eigen::Vector3d mid = 0.5 * (a + b);
    for (const auto& q : quads)
      for (const Eigen::Vector3i& t :
           {Eigen::Vector3i(q[0], q[1], q[2]), Eigen::Vector3i(q[0], q[2], q[3])}) {
        Eigen::Vector3i f = t.array() + base;
        const auto& v = mesh.vertices;
        const Eigen::Vector3d n = (v[f[1]] - v[f[0]]).cross(v[f[2]] - v[f[0]]);
        const bool out = n.dot((v[f[0]] + v[f[1]] + v[f[2]]) / 3.0 - mid) > 0.0;
        if (out != outward) std::swap(f[1], f[2]);
        mesh.faces.push_back(f);
      }
  };
  shell(lo, hi, true);
  shell(lo + Eigen::Vector3d::Constant(wall), hi - Eigen::Vector3d::Constant(wall), false);
  return mesh;
}

/// The solid axis-aligned box [lo, hi] (the outer shell of hollowBox).
TriangleMesh solidBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  TriangleMesh shell = hollowBox(lo, hi, 0.25 * (hi - lo).minCoeff());
  shell.faces.resize(12);  // the outer shell's 12 triangles come first
  shell.vertices.resize(8);
  return shell;
}

/// Accepted poses (of 200 draws, one attempt each) on `object` with geometry g, and how many of
/// them approach along z (the plate's large faces).
std::pair<int, int> posesAlongZ(const ObjectModel& object, const HandModel& h,
                                const EncloseGeometry& g) {
  const SamplerOptions o = encloseOptions(h);
  int accepted = 0, along_z = 0;
  for (std::uint64_t i = 0; i < 200; ++i) {
    Rng rng(11, i);
    const std::optional<Pose> pose =
        drawPalmEnclose(object, g, o.approach_axis, o.finger_points, 1, o.enclose_margin, rng);
    if (!pose) continue;
    ++accepted;
    const Eigen::Vector3d w = pose->orientation * o.approach_axis;
    if (std::abs(w.z()) > 0.9) ++along_z;
  }
  return {accepted, along_z};
}

TEST(PalmEnclose, ThinPartsAreNotClosedOverOntoThePalm) {
  // Plates 10 x 10 cm of thickness 4 mm and 2 cm, the barrett (min_depth 1 cm): a palm on a
  // large face of the thin plate has only 4 mm of part in front of it, its fingers would fold
  // over the plate onto the palm (self_collision), so no accepted pose approaches along z; on its
  // edges (10 cm deep) poses are accepted. Without the test (min_depth 0) the large faces are
  // taken too, and on the 2 cm plate (deeper than 1 cm) they are taken with it.
  const EncloseGeometry g = *encloseGeometry(barrett());
  ASSERT_DOUBLE_EQ(g.min_depth, 0.01);
  EncloseGeometry without = g;
  without.min_depth = 0.0;
  const ObjectModel thin = ObjectModel::fromMesh(
      solidBox(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.004)), "plate");
  const ObjectModel thick = ObjectModel::fromMesh(
      solidBox(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.02)), "slab");
  const auto [thin_accepted, thin_z] = posesAlongZ(thin, barrett(), g);
  EXPECT_GT(thin_accepted, 0);
  EXPECT_EQ(thin_z, 0) << "a palm on the 4 mm plate's face with the fingers across it";
  const auto [before_accepted, before_z] = posesAlongZ(thin, barrett(), without);
  EXPECT_GT(before_z, 10) << "without the test the plate's faces were taken (" << before_z << " of "
                          << before_accepted << ")";
  const auto [thick_accepted, thick_z] = posesAlongZ(thick, barrett(), g);
  EXPECT_GT(thick_z, 10) << "the 2 cm slab's faces (" << thick_z << " of " << thick_accepted << ")";
  g.validate();
  without.min_depth = -1e-3;
  EXPECT_TRUE(testing::throwsError([&] { without.validate(); }, {"min_depth"}));
}

TEST(PalmEnclose, ExtentThroughAHollowIsTheOuterOne) {
  // A hollow box (the box above with a 3 mm wall): the probe point lies in the cavity (probe
  // depth 5 mm and 13 mm) and the extent the fingers must span is the outer box's, not the
  // wall's; the same oracle holds with the outer box.
  const Eigen::Vector3d lo(-0.03, -0.04, 0.0), hi(0.03, 0.04, 0.12);
  const ObjectModel hollow = ObjectModel::fromMesh(hollowBox(lo, hi, 0.003), "hollow_box");
  ASSERT_TRUE(hollow.contains(Eigen::Vector3d(0.0, 0.0, 0.0015)));
  ASSERT_FALSE(hollow.contains(Eigen::Vector3d(0.0, 0.0, 0.06)));
  for (const HandModel* h : {&allegro(), &barrett()}) {
    SCOPED_TRACE(h->name());
    const auto [accepted, narrow] = checkBoxPoses(hollow, *h, lo, hi);
    EXPECT_GT(accepted, 20);
    EXPECT_GE(narrow, accepted * 85 / 100) << narrow << " of " << accepted;
  }
}

TEST(PalmEnclose, ProbeFallsBackFastWhereTheHandRarelyEnclosesTheObject) {
  // The YCB mug is wider than the barrett's span nearly everywhere: the construction-time probe
  // (64 attempts from generators of its own) finds too few poses for half the trials to find one
  // within 16 attempts, so its trials are the mixed sampler's (no attempt); on the box both
  // hands keep 16. The same on another thread.
  static const ObjectModel mug =
      ObjectModel::load(std::string(TEST_DATA_DIR) + "/real/objects/ycb_025_mug.obj");
  const Sampler on_mug(mug, encloseOptions(barrett()));
  EXPECT_EQ(on_mug.attemptsInForce(), 0);
  // Its trials are then the mixed sampler's: the same poses, volume on even trials.
  SamplerOptions mixed = encloseOptions(barrett());
  mixed.kind = SamplerKind::kMixed;
  const Sampler as_mixed(mug, mixed);
  for (std::uint64_t t = 0; t < 8; ++t) {
    EXPECT_EQ(on_mug.kindOfTrial(t), t % 2 == 0 ? SamplerKind::kVolume : SamplerKind::kSurface);
    EXPECT_EQ(on_mug.sample(5, t).position, as_mixed.sample(5, t).position);
    EXPECT_EQ(on_mug.sample(5, t).orientation.coeffs(), as_mixed.sample(5, t).orientation.coeffs());
  }
  EXPECT_EQ(Sampler(box(), encloseOptions(barrett())).attemptsInForce(), 16);
  EXPECT_EQ(Sampler(box(), encloseOptions(allegro())).attemptsInForce(), 16);
  int other = 0;
  std::thread th([&] { other = Sampler(mug, encloseOptions(barrett())).attemptsInForce(); });
  th.join();
  EXPECT_EQ(other, 0);
}

// The finger test skips points outside the object's grown bounds and tests remembered points
// first; an accepted pose must still pass the brute-force test: every open finger point outside
// the scanned banana and at least 0.5 mm off its surface, by the object's own queries.
TEST(PalmEnclose, AcceptedPosesKeepEveryFingerPointOffAScannedObject) {
  const ObjectModel banana =
      ObjectModel::load(std::string(TEST_DATA_DIR) + "/real/objects/ycb_011_banana.obj");
  const SamplerOptions o = encloseOptions(allegro());
  int accepted = 0;
  for (std::uint64_t trial = 0; trial < 40; ++trial) {
    Rng rng(7, trial);
    const std::optional<Pose> pose = drawPalmEnclose(banana, *o.enclose, o.approach_axis,
                                                     o.finger_points, 16, o.enclose_margin, rng);
    if (!pose) continue;
    ++accepted;
    const Eigen::Matrix3d r = pose->orientation.toRotationMatrix();
    for (const Eigen::Vector3d& p : o.finger_points) {
      const Eigen::Vector3d x = pose->position + r * p;
      ASSERT_FALSE(banana.contains(x)) << "trial " << trial;
      ASSERT_FALSE(banana.nearSurface(x, 5e-4)) << "trial " << trial;
    }
  }
  EXPECT_GT(accepted, 20);
}

TEST(PalmEnclose, PureFunctionOfSeedAndTrialOnAnyThread) {
  const Sampler s(box(), encloseOptions(allegro()));
  std::vector<Pose> here(64), there(64);
  for (std::uint64_t i = 0; i < 64; ++i) here[i] = s.sample(3, i);
  std::thread t([&] {
    for (std::uint64_t i = 64; i-- > 0;) there[i] = s.sample(3, i);
  });
  t.join();
  for (std::size_t i = 0; i < here.size(); ++i) {
    EXPECT_EQ(here[i].position, there[i].position);
    EXPECT_EQ(here[i].orientation.coeffs(), there[i].orientation.coeffs());
  }
  EXPECT_EQ(s.kindOfTrial(5), SamplerKind::kPalmEnclose);
}

TEST(PalmEnclose, CoarseToFineIsAPermutationSpreadOverTheList) {
  std::vector<Eigen::Vector3d> in;
  for (int i = 0; i < 11; ++i) in.emplace_back(i, 0.0, 0.0);
  std::vector<double> got;
  for (const Eigen::Vector3d& p : coarseToFine(in)) got.push_back(p.x());
  // 0, multiples of 8, of 4 (not 8), of 2 (not 4), then the odd indices.
  EXPECT_EQ(got, (std::vector<double>{0, 8, 4, 2, 6, 10, 1, 3, 5, 7, 9}));
  EXPECT_TRUE(coarseToFine({}).empty());
}

TEST(PalmEnclose, ErrorsNameWhatIsMissing) {
  EXPECT_EQ(samplerKindFromString("palm_enclose"), SamplerKind::kPalmEnclose);
  EXPECT_STREQ(toString(SamplerKind::kPalmEnclose), "palm_enclose");
  SamplerOptions o = encloseOptions(allegro());
  o.enclose.reset();
  EXPECT_TRUE(testing::throwsError([&] { Sampler s(box(), o); },
                                   {"palm_enclose sampler needs", "--sampler mixed"}));
  o = encloseOptions(allegro());
  o.enclose_margin = -1.0;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"enclose_margin"}));
  EncloseGeometry g = *encloseGeometry(allegro());
  g.span_max = g.span_min;
  EXPECT_TRUE(testing::throwsError([&] { g.validate(); }, {"span_min must be below span_max"}));
}

}  // namespace
}  // namespace taskmap
