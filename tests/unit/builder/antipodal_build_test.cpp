// A parallel-jaw build with the antipodal sampler: on a real scanned mesh (YCB banana, real
// Franka hand) it stores its grasps in fewer trials than the mixed sampler (trial counts, not
// time), the map is the same for any thread count, and the map records its sampler; the same for
// antipodal_palm on a jaw whose knuckles stand in front of its palm (test hand x soup can).
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "map_compare.hpp"
#include "sampler_build_fixture.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

const ObjectModel& banana() {
  return testing::realObject("objects/ycb_011_banana.obj");
}
const HandModel& franka() {
  return testing::realHand("hands/franka_hand/franka_hand.urdf");
}

BuildOptions jawBuild(SamplerKind kind, int threads) {
  return testing::samplerBuild(kind, threads, 12, 16);
}

TEST(AntipodalBuildTest, StoresJawGraspsInFewerTrialsThanTheMixedSampler) {
  const BuildResult mixed = buildMap(banana(), franka(), jawBuild(SamplerKind::kMixed, 2));
  const BuildResult anti = buildMap(banana(), franka(), jawBuild(SamplerKind::kAntipodal, 2));
  ASSERT_EQ(mixed.status, BuildStatus::kComplete) << mixed.message;
  ASSERT_EQ(anti.status, BuildStatus::kComplete) << anti.message;
  EXPECT_EQ(anti.map.grasps.size(), 12u);
  // Counts: the trials each needed for the same number of stored grasps (measured: 16 and 32);
  // at least half of the antipodal trials store a grasp.
  EXPECT_LE(anti.map.sampling.trials, 24u);
  EXPECT_LT(anti.map.sampling.trials, mixed.map.sampling.trials)
      << "antipodal " << anti.map.sampling.trials << " trials, mixed " << mixed.map.sampling.trials;
  EXPECT_EQ(anti.map.sampling.sampler, "antipodal");
  const nlohmann::json p = nlohmann::json::parse(anti.map.sampling.params_json);
  EXPECT_EQ(p.at("sampler"), "antipodal");
  EXPECT_NEAR(p.at("jaw_open_width").get<double>(), 0.08, 0.005);
  EXPECT_EQ(p.at("antipodal_friction").get<double>(), QualityOptions{}.friction);
}

TEST(AntipodalBuildTest, SameMapForAnyThreadCount) {
  const BuildResult one = buildMap(banana(), franka(), jawBuild(SamplerKind::kAntipodal, 1));
  ASSERT_EQ(one.status, BuildStatus::kComplete) << one.message;
  testing::expectSameMapContent(
      one.map, buildMap(banana(), franka(), jawBuild(SamplerKind::kAntipodal, 3)).map);
}

TEST(AntipodalBuildTest, PalmPlacementStoresInFewerTrialsThanMixedAndRecordsItself) {
  // antipodal_palm on the real Franka hand (palm grasps) and the YCB banana: trial counts for
  // the same 12 stored grasps, not times.
  const BuildResult mixed = buildMap(banana(), franka(), jawBuild(SamplerKind::kMixed, 2));
  const BuildResult palm = buildMap(banana(), franka(), jawBuild(SamplerKind::kAntipodalPalm, 2));
  ASSERT_EQ(palm.status, BuildStatus::kComplete) << palm.message;
  EXPECT_EQ(palm.map.grasps.size(), 12u);
  EXPECT_LT(palm.map.sampling.trials, mixed.map.sampling.trials)
      << "antipodal_palm " << palm.map.sampling.trials << " trials, mixed "
      << mixed.map.sampling.trials;
  // Its trials seldom end without the palm touching (the mixed sampler's do, often).
  const auto& out = palm.map.sampling.outcomes;
  const auto it = out.find("no_palm_contact");
  EXPECT_TRUE(it == out.end() || 4 * it->second < palm.map.sampling.trials);
  EXPECT_EQ(palm.map.sampling.sampler, "antipodal_palm");
  const nlohmann::json p = nlohmann::json::parse(palm.map.sampling.params_json);
  EXPECT_EQ(p.at("sampler"), "antipodal_palm");
  EXPECT_EQ(p.at("place_palm"), true);
  EXPECT_NEAR(p.at("jaw_palm_front").get<double>(), jawGeometry(franka())->palm_front, 1e-12);
  testing::expectSameMapContent(
      palm.map, buildMap(banana(), franka(), jawBuild(SamplerKind::kAntipodalPalm, 1)).map);
}

TEST(AntipodalBuildTest, KnuckledJawStoresPalmGraspsInFewerTrialsOnAnyThreadCount) {
  // A jaw whose knuckles stand in front of its palm (tests/data/hands/knuckle_jaw, as on a
  // Robotiq 2F-85) on the soup-can-sized cylinder: with the pads taken from the fingers'
  // distal links, antipodal_palm places the palm's front on the can between the knuckles.
  // Trial counts for the same 12 stored grasps (measured: 12 and 164), not times.
  const HandModel hand =
      HandModel::load(std::string(TEST_DATA_DIR) + "/hands/knuckle_jaw/knuckle_jaw.urdf");
  const ObjectModel can = ObjectModel::load(std::string(TEST_DATA_DIR) + "/meshes/soup_can.obj");
  const BuildResult mixed = buildMap(can, hand, jawBuild(SamplerKind::kMixed, 2));
  const BuildResult palm = buildMap(can, hand, jawBuild(SamplerKind::kAntipodalPalm, 2));
  ASSERT_EQ(mixed.status, BuildStatus::kComplete) << mixed.message;
  ASSERT_EQ(palm.status, BuildStatus::kComplete) << palm.message;
  EXPECT_EQ(palm.map.grasps.size(), 12u);
  EXPECT_LT(4 * palm.map.sampling.trials, mixed.map.sampling.trials)
      << "antipodal_palm " << palm.map.sampling.trials << " trials, mixed "
      << mixed.map.sampling.trials;
  const auto& out = palm.map.sampling.outcomes;
  const auto it = out.find("no_palm_contact");
  EXPECT_TRUE(it == out.end() || 10 * it->second < palm.map.sampling.trials);
  const nlohmann::json p = nlohmann::json::parse(palm.map.sampling.params_json);
  EXPECT_NEAR(p.at("jaw_open_width").get<double>(), jawGeometry(hand)->open_width, 1e-12);
  EXPECT_GT(p.at("jaw_open_width").get<double>(), 0.07);
  testing::expectSameMapContent(palm.map,
                                buildMap(can, hand, jawBuild(SamplerKind::kAntipodalPalm, 1)).map);
}

TEST(AntipodalBuildTest, MultiFingerHandIsRefusedWithAClearMessage) {
  const HandModel barrett =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  try {
    buildMap(banana(), barrett, jawBuild(SamplerKind::kAntipodal, 1));
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("parallel-jaw hand"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace taskmap
