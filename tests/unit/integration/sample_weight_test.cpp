// Sample weights of the quality criterion (task_map.hpp SampleWeight): epsilon, or epsilon x
// the physics hold margin, against an oracle that sums the mixture by hand; kAuto; errors.
#include <cmath>

#include <gtest/gtest.h>

#include "error_matchers.hpp"
#include "synthetic_map.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/integration/criteria.hpp"
#include "taskmap/integration/task_map.hpp"

namespace taskmap {
namespace {

using taskmap::testing::errorMessage;
using testing::randomPose;
using testing::syntheticMap;

constexpr std::size_t kMapSize = 300;
constexpr double kMaxTranslation = 0.04;  // m, recorded in params_json (not the default 0.05)
constexpr double kMaxRotation = 0.3;      // rad

/// Labels every grasp: a third do not hold, the others with displacements and rotations below
/// the limits; the limits recorded as the validator records them.
TaskMapData validatedMap() {
  TaskMapData data = syntheticMap(kMapSize);
  MapValidation v;
  Rng rng(11, 0);
  for (std::size_t i = 0; i < kMapSize; ++i) {
    const bool holds = i % 3 != 0;
    v.hold.push_back(holds ? 1 : 0);
    v.status.push_back(holds ? 0 : 3);
    v.translation.push_back(holds ? rng.uniform(0.0, kMaxTranslation) : 0.09);
    v.rotation.push_back(holds ? rng.uniform(0.0, kMaxRotation) : 0.1);
    v.direction.push_back(holds ? -1 : 2);
  }
  v.protocol = "dexgraspbench_fc";
  v.engine = "test";
  v.params_json = "{\"max_translation\": 0.04, \"max_rotation\": 0.3}";
  data.validation = v;
  return data;
}

/// The oracle's weight of grasp i under the hold margin.
double marginWeight(const TaskMapData& d, std::size_t i) {
  const MapValidation& v = *d.validation;
  if (v.hold[i] != 1) return 0.0;
  const double m =
      std::min(1.0 - v.translation[i] / kMaxTranslation, 1.0 - v.rotation[i] / kMaxRotation);
  return d.grasps.epsilon[i] * std::max(0.0, m);
}

/// Exact quality by hand with weights w(i).
template <class W>
double oracleQuality(const TaskMap& map, const Pose& x, W w) {
  const double sp = *map.options().position_sigma, sr = *map.options().rotation_sigma;
  double v = 0.0, wsum = 0.0;
  for (std::size_t i = 0; i < map.size(); ++i) {
    Twist g;
    v -= w(i) * gaussianDensity(x, map.pose(i), sp, sr, &g);
    wsum += w(i);
  }
  return v / wsum;
}

TEST(SampleWeight, HoldMarginWeighsEachSampleByEpsilonTimesItsMargin) {
  const TaskMapData data = validatedMap();
  const TaskMap map = TaskMap::fromData(data);
  EXPECT_EQ(map.options().sample_weight, SampleWeight::kHoldMargin);  // auto, fully validated
  Rng rng(5, 0);
  for (int k = 0; k < 40; ++k) {
    const Pose x = randomPose(rng);
    const double want = oracleQuality(map, x, [&](std::size_t i) { return marginWeight(data, i); });
    const QualityCriterion q = map.quality(x, std::nullopt, QualityMode::kExact);
    EXPECT_NEAR(q.value, want, 1e-10 * std::abs(want) + 1e-300);
  }
}

// With robust labels the margin is the robust test's: 0 for a grasp that is not robust (here
// every fourth of the holding ones), else how much of the margin (recorded in robust_json) the
// pushes from the closed state left.
TEST(SampleWeight, RobustLabelsWeighByTheMarginOfTheVariants) {
  TaskMapData data = validatedMap();
  MapValidation& v = *data.validation;
  constexpr double kMargin = 0.02, kMarginTurn = 0.1;
  v.robust_json =
      "{\"variants\": [\"nominal\", \"friction\"], \"margin_translation\": 0.02, "
      "\"margin_rotation\": 0.1}";
  Rng rng(12, 0);
  for (std::size_t i = 0; i < kMapSize; ++i) {
    const bool robust = v.hold[i] == 1 && i % 4 != 0;
    v.robust.push_back(robust ? 1 : 0);
    v.robust_share.push_back(robust ? 1.0 : 0.5);
    v.push_translation.push_back(robust ? rng.uniform(0.0, kMargin) : 0.03);
    v.push_rotation.push_back(robust ? rng.uniform(0.0, kMarginTurn) : 0.2);
    v.variant_held.insert(v.variant_held.end(), {robust ? std::uint8_t{1} : std::uint8_t{0},
                                                 robust ? std::uint8_t{1} : std::uint8_t{255}});
  }
  ASSERT_NO_THROW(data.validate());
  const TaskMap map = TaskMap::fromData(data);
  EXPECT_EQ(map.options().sample_weight, SampleWeight::kHoldMargin);
  const auto weight = [&](std::size_t i) {
    if (v.robust[i] != 1) return 0.0;
    const double m =
        std::min(1.0 - v.push_translation[i] / kMargin, 1.0 - v.push_rotation[i] / kMarginTurn);
    return data.grasps.epsilon[i] * std::max(0.0, m);
  };
  Rng poses(6, 0);
  for (int k = 0; k < 20; ++k) {
    const Pose x = randomPose(poses);
    const double want = oracleQuality(map, x, weight);
    const QualityCriterion q = map.quality(x, std::nullopt, QualityMode::kExact);
    EXPECT_NEAR(q.value, want, 1e-10 * std::abs(want) + 1e-300);
  }
}

TEST(SampleWeight, EpsilonIgnoresTheLabels) {
  const TaskMapData data = validatedMap();
  TaskMapOptions o;
  o.sample_weight = SampleWeight::kEpsilon;
  const TaskMap labelled = TaskMap::fromData(data, o);
  TaskMapData plain = data;
  plain.validation.reset();
  const TaskMap unlabelled = TaskMap::fromData(plain);  // auto on a map without labels: epsilon
  EXPECT_EQ(unlabelled.options().sample_weight, SampleWeight::kEpsilon);
  Rng rng(6, 0);
  for (int k = 0; k < 20; ++k) {
    const Pose x = randomPose(rng);
    const double want =
        oracleQuality(labelled, x, [&](std::size_t i) { return data.grasps.epsilon[i]; });
    EXPECT_NEAR(labelled.quality(x, std::nullopt, QualityMode::kExact).value, want,
                1e-10 * std::abs(want) + 1e-300);
    EXPECT_EQ(labelled.quality(x, std::nullopt, QualityMode::kExact).value,
              unlabelled.quality(x, std::nullopt, QualityMode::kExact).value);
  }
}

TEST(SampleWeight, NonHoldingSamplesDoNotPullTheGradient) {
  // A query on top of a grasp that does not hold: under the hold margin its own Gaussian is
  // absent, so the criterion equals the oracle without it and differs from the epsilon one.
  const TaskMapData data = validatedMap();
  TaskMapOptions eps;
  eps.sample_weight = SampleWeight::kEpsilon;
  const TaskMap by_margin = TaskMap::fromData(data);
  const TaskMap by_epsilon = TaskMap::fromData(data, eps);
  const Pose x = by_margin.pose(0);  // grasp 0 does not hold (i % 3 == 0)
  const QualityCriterion a = by_margin.quality(x, std::nullopt, QualityMode::kExact);
  const QualityCriterion b = by_epsilon.quality(x, std::nullopt, QualityMode::kExact);
  EXPECT_GT(a.value, b.value);  // less negative: the sample it sits on does not count
}

TEST(SampleWeight, PartialOrMissingLabelsAreRefusedForHoldMargin) {
  TaskMapData data = validatedMap();
  data.validation->hold[7] = MapValidation::kNotTested;
  data.validation->status[7] = MapValidation::kNotTested;
  EXPECT_EQ(TaskMap::fromData(data).options().sample_weight,
            SampleWeight::kEpsilon);  // auto: not all
  TaskMapOptions o;
  o.sample_weight = SampleWeight::kHoldMargin;
  const std::string m = errorMessage([&] { TaskMap::fromData(data, o); });
  EXPECT_NE(m.find("299 of 300"), std::string::npos) << m;
  EXPECT_NE(m.find("taskmap validate"), std::string::npos) << m;
  data.validation.reset();
  EXPECT_NE(errorMessage([&] { TaskMap::fromData(data, o); }).find("0 of 300"), std::string::npos);
}

TEST(SampleWeight, NamesRoundTripAndUnknownNamesAreRefused) {
  for (SampleWeight w : {SampleWeight::kAuto, SampleWeight::kEpsilon, SampleWeight::kHoldMargin})
    EXPECT_EQ(sampleWeightFromString(toString(w)), w);
  const std::string m = errorMessage([] { sampleWeightFromString("holding"); });
  EXPECT_NE(m.find("hold_margin"), std::string::npos) << m;
}

}  // namespace
}  // namespace taskmap
