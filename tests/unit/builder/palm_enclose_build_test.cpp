// A multi-finger build with the palm_enclose sampler: on a real scanned mesh (YCB banana, real
// Allegro hand, both in tests/data/real) it stores its grasps in fewer trials than the mixed
// sampler and few of its trials end without the palm (trial counts, not time), the map is the
// same for any thread count, and the map records its sampler and the hand geometry it used.
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
const HandModel& allegro() {
  return testing::realHand("hands/allegro_right/allegro_hand_description_right.urdf");
}

BuildOptions encloseBuild(SamplerKind kind, int threads) {
  return testing::samplerBuild(kind, threads, 10, 8);
}

TEST(PalmEncloseBuildTest, StoresInFewerTrialsThanMixedWithThePalmTouching) {
  const BuildResult mixed = buildMap(banana(), allegro(), encloseBuild(SamplerKind::kMixed, 2));
  const BuildResult palm =
      buildMap(banana(), allegro(), encloseBuild(SamplerKind::kPalmEnclose, 2));
  ASSERT_EQ(mixed.status, BuildStatus::kComplete) << mixed.message;
  ASSERT_EQ(palm.status, BuildStatus::kComplete) << palm.message;
  EXPECT_EQ(palm.map.grasps.size(), 10u);
  // Counts for the same 10 stored grasps, not times: at most 4 trials per stored grasp (the
  // bench measured 1.3 on this pair with 100 grasps), fewer than half of mixed's.
  EXPECT_LE(palm.map.sampling.trials, 40u);
  EXPECT_LT(2 * palm.map.sampling.trials, mixed.map.sampling.trials)
      << "palm_enclose " << palm.map.sampling.trials << " trials, mixed "
      << mixed.map.sampling.trials;
  const auto& out = palm.map.sampling.outcomes;
  const auto it = out.find("no_palm_contact");
  EXPECT_TRUE(it == out.end() || 10 * it->second < palm.map.sampling.trials)
      << it->second << " of " << palm.map.sampling.trials << " trials without the palm";
  EXPECT_EQ(palm.map.sampling.sampler, "palm_enclose");
  const nlohmann::json p = nlohmann::json::parse(palm.map.sampling.params_json);
  EXPECT_EQ(p.at("sampler"), "palm_enclose");
  EXPECT_EQ(p.at("attempts"), 16);
  EXPECT_EQ(p.at("enclose_margin").get<double>(), SamplerOptions{}.enclose_margin);
  const EncloseGeometry g = *encloseGeometry(allegro());
  EXPECT_NEAR(p.at("enclose_span").get<double>(), g.span_max - g.span_min, 1e-12);
}

TEST(PalmEncloseBuildTest, SameMapForAnyThreadCount) {
  const BuildResult one = buildMap(banana(), allegro(), encloseBuild(SamplerKind::kPalmEnclose, 1));
  ASSERT_EQ(one.status, BuildStatus::kComplete) << one.message;
  testing::expectSameMapContent(
      one.map, buildMap(banana(), allegro(), encloseBuild(SamplerKind::kPalmEnclose, 3)).map);
}

TEST(PalmEncloseBuildTest, HandWithoutClosingFingersIsRefusedWithAClearMessage) {
  // The URDF alone (no sidecar): no fingers, no closing motion, so no enclose geometry.
  const HandModel bare = HandModel::loadKinematics(
      std::string(TEST_DATA_DIR) + "/real/hands/allegro_right/allegro_hand_description_right.urdf");
  try {
    buildMap(banana(), bare, encloseBuild(SamplerKind::kPalmEnclose, 1));
    FAIL() << "expected an Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("palm_enclose sampler needs"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace taskmap
