// The palm_enclose sampler of multi-finger hands (real Allegro hand of tests/data/real, the
// bundled barrett): the hand geometry from its shapes (closing axis across the approach, palm
// front = the palm points' front-most coordinate), and on the reference box (6 x 8 x 12 cm,
// axis-aligned) an oracle for every accepted pose: the approach along a face's inward normal,
// the palm's front in that face's plane, the closing axis along the narrowest box extent across
// the approach (within the candidate spacing pi / kEncloseRolls / 2), the open fingers outside;
// then determinism on another thread and the option errors.
#include <algorithm>
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
  }
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
TEST(PalmEnclose, PalmOnTheFaceFingersAcrossTheNarrowExtent) {
  const Eigen::Vector3d lo(-0.03, -0.04, 0.0), hi(0.03, 0.04, 0.12);
  for (const HandModel* h : {&allegro(), &barrett()}) {
    SCOPED_TRACE(h->name());
    const SamplerOptions o = encloseOptions(*h);
    const EncloseGeometry& g = *o.enclose;
    const double m = o.enclose_margin, span = g.span_max - g.span_min - 2.0 * m;
    int accepted = 0, narrow = 0;
    for (std::uint64_t i = 0; i < 200; ++i) {
      Rng rng(7, i);
      const std::optional<Pose> pose =
          drawPalmEnclose(box(), g, o.approach_axis, o.finger_points, 1, m, rng);
      if (!pose) continue;
      ++accepted;
      const Eigen::Matrix3d r = pose->orientation.toRotationMatrix();
      const Eigen::Vector3d w = r * o.approach_axis, c = r * g.closing_axis, v = c.cross(w);
      int k = 0;
      w.cwiseAbs().maxCoeff(&k);
      ASSERT_NEAR(std::abs(w[k]), 1.0, 1e-9) << "approach not along a face normal";
      // The face the palm is on: w points into the box, so the face is at hi[k] when w[k] < 0.
      const double face = w[k] < 0 ? hi[k] : lo[k];
      EXPECT_NEAR(w.dot(pose->position) + g.palm_front, w[k] * face, 1e-6)
          << "the palm's front is not in the face plane";
      EXPECT_NEAR(c.dot(w), 0.0, 1e-9);
      const double depth = std::min(g.probe_depth, 0.5 * (hi[k] - lo[k]));
      const Eigen::Vector3d y0 =
          pose->position + (g.palm_front + depth) * w + g.grasp_centre.y() * v;
      const auto [s0, s1] = boxChord(lo, hi, y0, c);
      ASSERT_LT(s0, s1) << "the closing line misses the box";
      const double width = s1 - s0;
      EXPECT_LE(width, span + 1e-6);
      const double centre = std::clamp(g.grasp_centre.x(), g.span_min + m + 0.5 * width,
                                       g.span_max - m - 0.5 * width);
      EXPECT_NEAR(0.5 * (s0 + s1), centre, 1e-6) << "chord not centred on the grasp centre";
      double narrowest = 1e300;
      for (int j = 0; j < 3; ++j)
        if (j != k) narrowest = std::min(narrowest, hi[j] - lo[j]);
      if (width <= narrowest / std::cos(M_PI / kEncloseRolls / 2.0) + 1e-6) ++narrow;
      for (const Eigen::Vector3d& p : o.finger_points)
        ASSERT_FALSE(box().contains(pose->position + r * p)) << "open finger inside the box";
    }
    EXPECT_GT(accepted, 20);
    EXPECT_GE(narrow, accepted * 9 / 10) << narrow << " of " << accepted;
  }
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
