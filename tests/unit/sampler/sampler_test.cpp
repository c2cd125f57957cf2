// Sampler: determinism per (seed, trial), uniformity against closed-form expectations, surface
// approach geometry, mixed parity, option errors.
#include "taskmap/sampler/sampler.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/random.hpp"
#include "test_meshes.hpp"

namespace taskmap {
namespace {

const ObjectModel& box() {
  static const ObjectModel object = ObjectModel::fromMesh(
      testing::makeBox(0.4, 0.2, 0.1, Eigen::Vector3d(0.2, 0.1, 0.05)), "box");
  return object;
}

SamplerOptions optionsOf(SamplerKind kind) {
  SamplerOptions o;
  o.kind = kind;
  o.approach_axis = Eigen::Vector3d(0.0, 0.6, 0.8);
  return o;
}

TEST(SamplerTest, KindNamesRoundTrip) {
  for (auto k :
       {SamplerKind::kVolume, SamplerKind::kSurface, SamplerKind::kMixed, SamplerKind::kAntipodal,
        SamplerKind::kEnclose, SamplerKind::kAntipodalPalm, SamplerKind::kPalmEnclose})
    EXPECT_EQ(samplerKindFromString(toString(k)), k);
  EXPECT_TRUE(testing::throwsError(
      [&] { samplerKindFromString("random"); },
      {"volume, surface, mixed, antipodal, enclose, antipodal_palm or palm_enclose"}));
}

TEST(SamplerTest, InvalidOptionsAreRefused) {
  SamplerOptions o;
  o.approach_axis = Eigen::Vector3d(1, 1, 0);
  EXPECT_THROW(o.validate(), Error);
  EXPECT_THROW(Sampler(box(), o), Error);
  o = SamplerOptions{};
  o.standoff_min = 0.1;
  o.standoff_max = 0.0;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"standoff_min"}));
  o = SamplerOptions{};
  o.standoff_max = std::nan("");
  EXPECT_THROW(o.validate(), Error);
  EXPECT_NO_THROW(SamplerOptions{}.validate());
}

TEST(SamplerTest, SameSeedAndTrialGiveTheSamePoseInAnyOrder) {
  for (auto kind : {SamplerKind::kVolume, SamplerKind::kSurface, SamplerKind::kMixed}) {
    const Sampler a(box(), optionsOf(kind)), b(box(), optionsOf(kind));
    std::vector<Eigen::Matrix<double, 7, 1>> forward;
    for (std::uint64_t t = 0; t < 50; ++t) forward.push_back(a.sample(9, t).toVector7());
    for (std::uint64_t t = 50; t-- > 0;) EXPECT_EQ(b.sample(9, t).toVector7(), forward[t]);
    int same_seed_other = 0;
    for (std::uint64_t t = 0; t < 50; ++t)
      same_seed_other += a.sample(10, t).toVector7() == forward[t];
    EXPECT_EQ(same_seed_other, 0);
    for (std::uint64_t t = 1; t < 50; ++t) EXPECT_NE(forward[t], forward[t - 1]);
  }
}

TEST(SamplerTest, VolumeSamplesAreUniformInsideWithUniformRotations) {
  const Sampler s(box(), optionsOf(SamplerKind::kVolume));
  const int n = 4000;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix3d mean_r = Eigen::Matrix3d::Zero();
  int left_half = 0;
  for (int i = 0; i < n; ++i) {
    const Pose p = s.sample(3, static_cast<std::uint64_t>(i));
    ASSERT_TRUE(box().contains(p.position)) << p.position.transpose();
    EXPECT_NEAR(p.orientation.norm(), 1.0, 1e-12);
    mean += p.position / n;
    mean_r += p.orientation.toRotationMatrix() / n;
    left_half += p.position.x() < 0.2;
  }
  // Uniform in the box: mean at the centre (std of the mean ~ 0.4/sqrt(12 n) = 0.0018 in x).
  EXPECT_LT((mean - Eigen::Vector3d(0.2, 0.1, 0.05)).cwiseAbs().maxCoeff(), 0.01);
  EXPECT_NEAR(left_half / static_cast<double>(n), 0.5, 0.04);
  // Uniform on SO(3): E[R] = 0 (each entry has std 1/sqrt(3n) ~ 0.009 here).
  EXPECT_LT(mean_r.cwiseAbs().maxCoeff(), 0.05) << mean_r;
}

TEST(SamplerTest, SurfaceSamplesApproachAlongTheInwardNormalWithinTheStandoff) {
  SamplerOptions o = optionsOf(SamplerKind::kSurface);
  o.standoff_min = -0.01;
  o.standoff_max = 0.02;
  const Sampler s(box(), o);
  const int n = 3000;
  // Face areas: +-x 0.02, +-y 0.04, +-z 0.08 (total 0.28).
  int on_x = 0, on_y = 0, on_z = 0, outside = 0;
  double roll_cos = 0.0, roll_sin = 0.0;
  for (int i = 0; i < n; ++i) {
    const Pose p = s.sample(5, static_cast<std::uint64_t>(i));
    const Eigen::Vector3d approach = p.orientation * o.approach_axis;
    // Approach direction is an inward box normal: one axis, unit.
    int axis = -1;
    approach.cwiseAbs().maxCoeff(&axis);
    ASSERT_NEAR(std::abs(approach[axis]), 1.0, 1e-9) << approach.transpose();
    const Eigen::Vector3d outward = -approach;
    // The palm is within the standoff range of the face along the normal.
    const double face = outward[axis] > 0 ? (axis == 0 ? 0.4 : axis == 1 ? 0.2 : 0.1) : 0.0;
    const double standoff = (p.position[axis] - face) * (outward[axis] > 0 ? 1.0 : -1.0);
    EXPECT_GE(standoff, -0.01 - 1e-12);
    EXPECT_LE(standoff, 0.02 + 1e-12);
    outside += standoff > 0;
    (axis == 0 ? on_x : axis == 1 ? on_y : on_z)++;
    // Roll: angle of the palm's x axis about the normal, measured against a fixed reference.
    const Eigen::Vector3d ref = axis == 0 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitX();
    const Eigen::Vector3d x = p.orientation * Eigen::Vector3d(1, 0, 0);
    const Eigen::Vector3d in_plane = x - x.dot(outward) * outward;
    if (in_plane.norm() > 1e-6) {
      roll_cos += in_plane.normalized().dot(ref) / n;
      roll_sin += in_plane.normalized().dot(outward.cross(ref)) / n;
    }
  }
  EXPECT_NEAR(on_x / static_cast<double>(n), 0.02 / 0.14, 0.03);
  EXPECT_NEAR(on_y / static_cast<double>(n), 0.04 / 0.14, 0.03);
  EXPECT_NEAR(on_z / static_cast<double>(n), 0.08 / 0.14, 0.03);
  EXPECT_NEAR(outside / static_cast<double>(n), 2.0 / 3.0, 0.04);
  // Uniform roll: the mean direction vanishes.
  EXPECT_LT(std::hypot(roll_cos, roll_sin), 0.06);
}

TEST(SamplerTest, MixedAlternatesVolumeAndSurfaceByTrialParity) {
  const Sampler mixed(box(), optionsOf(SamplerKind::kMixed));
  const Sampler volume(box(), optionsOf(SamplerKind::kVolume));
  const Sampler surface(box(), optionsOf(SamplerKind::kSurface));
  for (std::uint64_t t = 0; t < 40; ++t) {
    EXPECT_EQ(mixed.kindOfTrial(t), t % 2 == 0 ? SamplerKind::kVolume : SamplerKind::kSurface);
    const Sampler& same = t % 2 == 0 ? volume : surface;
    EXPECT_EQ(mixed.sample(2, t).toVector7(), same.sample(2, t).toVector7());
  }
  EXPECT_EQ(volume.kindOfTrial(1), SamplerKind::kVolume);
  EXPECT_EQ(surface.kindOfTrial(0), SamplerKind::kSurface);
}

TEST(SamplerTest, AlignAxisMapsTheAxisEvenWhenAntiparallel) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 2).normalized();
  for (const Eigen::Vector3d& dir : {Eigen::Vector3d(-axis), Eigen::Vector3d(axis),
                                     Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0.6, -0.8, 0)}) {
    for (double roll : {0.0, 1.0, -2.5}) {
      const Eigen::Quaterniond q = alignAxis(axis, dir, roll);
      EXPECT_NEAR(q.norm(), 1.0, 1e-12);
      EXPECT_LT((q * axis - dir).norm(), 1e-9) << dir.transpose() << " roll " << roll;
    }
    // Roll turns a perpendicular vector by the roll angle about dir.
    const Eigen::Vector3d perp = axis.unitOrthogonal();
    const Eigen::Vector3d a = alignAxis(axis, dir, 0.0) * perp;
    const Eigen::Vector3d b = alignAxis(axis, dir, 0.7) * perp;
    EXPECT_NEAR(std::atan2(a.cross(b).dot(dir), a.dot(b)), 0.7, 1e-9);
  }
}

}  // namespace
}  // namespace taskmap

namespace taskmap {
namespace {

// The enclose sampler's finger check (the finger points grouped by 1 cm cube, a group skipped
// when its bounding ball lies outside the object) accepts exactly the poses the brute force
// does, every point tested: the oracle replays each trial's attempts (a surface point, a roll,
// the palm on the point) and the sampler's pose is the first attempt the oracle accepts. The
// block of 1377 finger points beside the palm, on the YCB banana.
TEST(SamplerTest, GroupedFingerCheckAcceptsWhatTheBruteForceAccepts) {
  const ObjectModel banana =
      ObjectModel::load(std::string(TEST_DATA_DIR) + "/real/objects/ycb_011_banana.obj");
  SamplerOptions o;
  o.kind = SamplerKind::kEnclose;
  // A finger as dense as a hull's points: a 2 x 2 x 4 cm block beside the palm, reaching
  // along the approach, points 2.5 mm apart (64 or more in a 1 cm cube).
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j)
      for (int k = 0; k <= 16; ++k)
        o.finger_points.emplace_back(0.02 + 0.0025 * i, -0.01 + 0.0025 * j, 0.0025 * k);
  const Sampler s(banana, o);
  int accepted = 0, refused = 0;
  for (std::uint64_t t = 0; t < 120; ++t) {
    Rng rng(3, t);
    for (int k = 0; k < o.attempts; ++k) {
      const SurfaceSample q = banana.sampleSurface(rng);
      Pose pose;
      pose.orientation = alignAxis(o.approach_axis, -q.normal, rng.uniform(0.0, 2.0 * M_PI));
      pose.position = q.point;
      bool outside = true;
      for (const Eigen::Vector3d& p : o.finger_points)
        outside = outside && !banana.contains(pose.position + pose.orientation * p);
      if (!outside) {
        ++refused;
        continue;
      }
      ++accepted;
      const Pose got = s.sample(3, t);
      EXPECT_EQ(got.position, pose.position) << "trial " << t;
      EXPECT_EQ(got.orientation.coeffs(), pose.orientation.coeffs()) << "trial " << t;
      break;
    }
  }
  std::printf("accepted %d, refused attempts %d\n", accepted, refused);
  EXPECT_GT(accepted, 30);
  EXPECT_GT(refused, 30);
}

}  // namespace
}  // namespace taskmap
