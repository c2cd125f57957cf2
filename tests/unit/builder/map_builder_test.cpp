// The build pipeline: identical maps for any thread count or block size, the first K valid
// grasps in trial order (checked against a sequential brute-force oracle), budgets, stop flag.
#include "taskmap/builder/map_builder.hpp"

#include <unistd.h>

#include <cstdio>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "build_fixtures.hpp"
#include "map_compare.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

constexpr auto box = &testing::boxObject;
constexpr auto panda = &testing::pandaHand;

// Force-closure grasps per test build (small: these tests also run under sanitizers).
constexpr std::uint64_t kValid = 4;

BuildOptions smallBuild(int threads) {
  BuildOptions o;
  o.seed = 11;
  o.valid_target = kValid;
  o.max_trials = 3000;
  o.threads = threads;
  o.block_size = 4;
  return o;
}

TEST(MapBuilderTest, IdenticalMapsForOneTwoAndEightThreads) {
  const BuildResult one = buildMap(box(), panda(), smallBuild(1));
  ASSERT_EQ(one.status, BuildStatus::kComplete) << one.message;
  EXPECT_EQ(one.map.grasps.size(), kValid);
  for (int threads : {2, 8}) {
    SCOPED_TRACE(threads);
    testing::expectSameMapContent(one.map, buildMap(box(), panda(), smallBuild(threads)).map);
  }
}

TEST(MapBuilderTest, BlockSizeDoesNotChangeTheMap) {
  BuildOptions a = smallBuild(2), b = smallBuild(2);
  a.block_size = 1;
  b.block_size = 64;
  testing::expectSameMapContent(buildMap(box(), panda(), a).map, buildMap(box(), panda(), b).map);
}

TEST(MapBuilderTest, MatchesSequentialOracle) {
  const BuildOptions options = smallBuild(2);
  const BuildResult r = buildMap(box(), panda(), options);
  ASSERT_EQ(r.status, BuildStatus::kComplete);
  // Oracle: trials one by one, in index order, with the same stages.
  SamplerOptions so = options.sampler;
  so.approach_axis = panda().approachAxis();
  const Sampler sampler(box(), so);
  const GraspSimulator sim(box(), panda(), options.simulation);
  const MassProperties& mp = box().massProperties();
  std::vector<Eigen::Matrix<double, 7, 1>> poses;
  std::vector<double> eps;
  std::map<std::string, std::uint64_t> outcomes;
  std::uint64_t trials = 0;
  while (poses.size() < options.valid_target) {
    const GraspResult g = sim.simulate(sampler.sample(options.seed, trials++));
    if (g.status != GraspStatus::kOk) {
      ++outcomes[toString(g.status)];
      continue;
    }
    const QualityResult q = evaluateGrasp(g.contacts, mp.center_of_mass, mp.torque_scale);
    ++outcomes[q.force_closure ? "force_closure" : "not_force_closure"];
    if (q.force_closure) {
      poses.push_back(g.pose.toVector7());
      eps.push_back(q.epsilon);
    }
  }
  EXPECT_EQ(r.map.sampling.trials, trials);
  EXPECT_EQ(r.map.sampling.outcomes, outcomes);
  ASSERT_EQ(r.map.grasps.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_EQ(r.map.grasps.pose.row(static_cast<Eigen::Index>(i)).transpose(), poses[i]);
    EXPECT_EQ(r.map.grasps.epsilon[i], eps[i]);
    EXPECT_EQ(r.map.grasps.force_closure[i], 1);
  }
  EXPECT_GE(r.timing.trials_simulated, trials);
  EXPECT_GT(r.timing.simulation_seconds, 0.0);
}

TEST(MapBuilderTest, KeepInvalidStoresEveryCompletedTrial) {
  BuildOptions o = smallBuild(2);
  o.keep_invalid = true;
  const BuildResult all = buildMap(box(), panda(), o);
  const BuildResult valid = buildMap(box(), panda(), smallBuild(2));
  EXPECT_EQ(all.map.sampling.trials, valid.map.sampling.trials);
  const auto& out = all.map.sampling.outcomes;
  const std::uint64_t ok = (out.count("force_closure") ? out.at("force_closure") : 0) +
                           (out.count("not_force_closure") ? out.at("not_force_closure") : 0);
  EXPECT_EQ(all.map.grasps.size(), ok);
  // The force-closure rows are exactly the default map.
  Eigen::Index row = 0;
  for (std::size_t i = 0; i < all.map.grasps.size(); ++i)
    if (all.map.grasps.force_closure[i]) {
      EXPECT_EQ(all.map.grasps.pose.row(static_cast<Eigen::Index>(i)),
                valid.map.grasps.pose.row(row++));
    }
  EXPECT_EQ(row, static_cast<Eigen::Index>(kValid));
}

TEST(MapBuilderTest, TrialBudgetExhausted) {
  BuildOptions o = smallBuild(2);
  o.valid_target = 100000;
  o.max_trials = 10;
  const BuildResult r = buildMap(box(), panda(), o);
  EXPECT_EQ(r.status, BuildStatus::kTrialBudgetExhausted);
  EXPECT_EQ(r.map.sampling.trials, 10u);
  std::uint64_t sum = 0;
  for (const auto& [name, count] : r.map.sampling.outcomes) sum += count;
  EXPECT_EQ(sum, 10u);
  EXPECT_NE(r.message.find("trial budget"), std::string::npos);
  EXPECT_NO_THROW(r.map.validate());
}

TEST(MapBuilderTest, StopFlagInterrupts) {
  std::atomic<bool> stop{true};
  const BuildResult r = buildMap(box(), panda(), smallBuild(2), {}, &stop);
  EXPECT_EQ(r.status, BuildStatus::kInterrupted);
  EXPECT_EQ(r.map.sampling.trials, 0u);
  EXPECT_EQ(r.map.grasps.size(), 0u);
}

TEST(MapBuilderTest, ProgressIsReported) {
  int calls = 0;
  BuildProgress last;
  buildMap(
      box(), panda(), smallBuild(2),
      [&](const BuildProgress& p) {
        ++calls;
        EXPECT_GE(p.trials_done, last.trials_done);
        last = p;
      },
      nullptr, 0.001);
  EXPECT_GE(calls, 1);
  EXPECT_EQ(last.valid_target, kValid);
  EXPECT_GE(last.valid_found, kValid);
}

TEST(MapBuilderTest, ExceptionFromTheProgressCallbackReachesTheCaller) {
  EXPECT_THROW(buildMap(
                   box(), panda(), smallBuild(2),
                   [](const BuildProgress&) { throw Error("callback failed"); }, nullptr, 0.001),
               Error);
}

TEST(MapBuilderTest, BuiltMapSurvivesWriteAndRead) {
  const BuildResult r = buildMap(box(), panda(), smallBuild(2));
  const std::string path = ::testing::TempDir() + "built_" + std::to_string(::getpid()) + ".h5";
  writeMap(path, r.map);
  const TaskMapData back = readMap(path);
  testing::expectSameMapContent(r.map, back);
  EXPECT_EQ(back.hand.joint_names, panda().jointNames());
  EXPECT_EQ(back.grasps.rotation_scale, panda().rotationScale());
  EXPECT_EQ(back.sampling.params_json, r.map.sampling.params_json);
  std::remove(path.c_str());
}

TEST(MapBuilderTest, InvalidOptionsAreRefused) {
  BuildOptions o;
  o.valid_target = 0;
  EXPECT_THROW(o.validate(), Error);
  o = BuildOptions{};
  o.threads = -1;
  EXPECT_THROW(o.validate(), Error);
  o = BuildOptions{};
  o.extra_params_json = "[1, 2]";
  EXPECT_THROW(o.validate(), Error);
  o = BuildOptions{};
  o.quality.friction = -1;
  EXPECT_THROW(o.validate(), Error);
  EXPECT_NO_THROW(BuildOptions{}.validate());
}

}  // namespace
}  // namespace taskmap
