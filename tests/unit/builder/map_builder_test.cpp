// The build pipeline: identical maps for any thread count or block size, the first K valid
// grasps in trial order (checked against a sequential brute-force oracle), budgets, stop flag.
#include "taskmap/builder/map_builder.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "build_fixtures.hpp"
#include "error_matchers.hpp"
#include "map_compare.hpp"
#include "taskmap/builder/size_check.hpp"
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

// The sampler options a build gives the panda for `kind` (unset: the hand's default), written
// out here rather than taken from the builder.
SamplerOptions pandaSampler(std::optional<SamplerKind> kind) {
  SamplerOptions so;
  so.kind = kind;
  so.approach_axis = panda().approachAxis();
  if (!kind) {
    so.jaws = jawGeometry(panda());
    so.finger_points = fingerCheckPoints(panda(), 0.01);
    so.place_palm = true;
  }
  return so;
}

// The build against trials run one by one, in index order, with the same stages.
void expectSequentialOracle(const BuildOptions& options, const SamplerOptions& so) {
  const BuildResult r = buildMap(box(), panda(), options);
  ASSERT_EQ(r.status, BuildStatus::kComplete);
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

// The default sampler (antipodal_palm for the panda) and mixed.
TEST(MapBuilderTest, MatchesSequentialOracle) {
  for (const std::optional<SamplerKind> kind :
       {std::optional<SamplerKind>(), std::optional(SamplerKind::kMixed)}) {
    SCOPED_TRACE(kind ? toString(*kind) : "default");
    BuildOptions options = smallBuild(2);
    options.sampler.kind = kind;
    expectSequentialOracle(options, pandaSampler(kind));
  }
}

TEST(MapBuilderTest, VolumeIsOptionalAndLeavesTheGraspsAsTheyWere) {
  // Default (buildQualityDefaults): force closure and epsilon only, volume 0, params say so.
  const BuildResult lean = buildMap(box(), panda(), smallBuild(2));
  ASSERT_EQ(lean.status, BuildStatus::kComplete) << lean.message;
  EXPECT_EQ(BuildOptions().quality.volume, VolumeMode::kNever);
  for (double v : lean.map.grasps.volume) EXPECT_EQ(v, 0.0);
  EXPECT_NE(lean.map.sampling.params_json.find("\"volume\":\"never\""), std::string::npos);
  // The previous build (volume of every stored grasp): the same trials, grasps and epsilons.
  BuildOptions o = smallBuild(2);
  o.quality.volume = VolumeMode::kForceClosure;
  const BuildResult full = buildMap(box(), panda(), o);
  ASSERT_EQ(full.map.grasps.size(), lean.map.grasps.size());
  EXPECT_EQ(full.map.sampling.trials, lean.map.sampling.trials);
  EXPECT_EQ(full.map.sampling.outcomes, lean.map.sampling.outcomes);
  EXPECT_EQ(full.map.grasps.pose, lean.map.grasps.pose);
  EXPECT_EQ(full.map.grasps.epsilon, lean.map.grasps.epsilon);
  for (double v : full.map.grasps.volume) EXPECT_GT(v, 0.0);
  EXPECT_NE(full.map.sampling.params_json.find("\"volume\":\"force_closure\""), std::string::npos);
}

TEST(MapBuilderTest, ContactReductionIsRecordedAndDeterministic) {
  BuildOptions o = smallBuild(1);
  o.quality.contacts_per_link = 2;
  const BuildResult one = buildMap(box(), panda(), o);
  ASSERT_EQ(one.status, BuildStatus::kComplete) << one.message;
  EXPECT_NE(one.map.sampling.params_json.find("\"contacts_per_link\":2"), std::string::npos);
  o.threads = 2;
  testing::expectSameMapContent(one.map, buildMap(box(), panda(), o).map);
  // Absent from the params when every contact enters the hull.
  EXPECT_EQ(
      buildMap(box(), panda(), smallBuild(1)).map.sampling.params_json.find("contacts_per_link"),
      std::string::npos);
}

TEST(MapBuilderTest, TrialsPastTheTargetAreNotSimulated) {
  // One thread, one block of every trial: the trials past the one that completes the valid
  // target are neither simulated nor scored, and the map is the one of blocks of one trial.
  BuildOptions big = smallBuild(1), single = smallBuild(1);
  big.block_size = 3000;
  single.block_size = 1;
  const BuildResult a = buildMap(box(), panda(), big);
  const BuildResult b = buildMap(box(), panda(), single);
  ASSERT_EQ(a.status, BuildStatus::kComplete) << a.message;
  testing::expectSameMapContent(a.map, b.map);
  EXPECT_EQ(a.timing.trials_simulated, a.map.sampling.trials);  // not the block's 3000
  EXPECT_EQ(b.timing.trials_simulated, b.map.sampling.trials);
  EXPECT_LT(a.map.sampling.trials, 3000u);
  const auto& out = a.map.sampling.outcomes;
  const std::uint64_t ok_to_target =
      out.at("force_closure") + (out.count("not_force_closure") ? out.at("not_force_closure") : 0);
  EXPECT_EQ(a.timing.grasps_scored, ok_to_target);
  EXPECT_EQ(b.timing.grasps_scored, ok_to_target);
}

TEST(MapBuilderTest, KeepInvalidStoresEveryCompletedTrial) {
  BuildOptions o = smallBuild(2);
  o.stored = StoredGrasps::kAllCompleted;
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
  o.max_trials = 200;
  const BuildResult r = buildMap(box(), panda(), o);
  EXPECT_EQ(r.status, BuildStatus::kTrialBudgetExhausted);
  EXPECT_EQ(r.map.sampling.trials, 200u);
  EXPECT_GT(r.map.grasps.size(), 0u);
  std::uint64_t sum = 0;
  for (const auto& [name, count] : r.map.sampling.outcomes) sum += count;
  EXPECT_EQ(sum, 200u);
  EXPECT_NE(r.message.find("trial budget"), std::string::npos);
  EXPECT_NO_THROW(r.map.validate());
}

TEST(MapBuilderTest, NoGraspStoredNamesTheDominantOutcome) {
  // The panda with its approach axis reversed backs away from the object: no trial keeps
  // palm contact, and the build says so instead of returning an empty map as complete.
  const std::string dir = ::testing::TempDir() + "/reversed_panda_" + std::to_string(::getpid());
  ASSERT_EQ(std::system(("mkdir -p " + dir).c_str()), 0);
  const std::string src = std::string(TASKMAP_HANDS_DIR) + "/panda/panda";
  ASSERT_EQ(std::system(("cp " + src + ".urdf " + dir + "/panda.urdf").c_str()), 0);
  ASSERT_EQ(std::system(("sed 's/\"approach_axis\": \\[0, 0, 1\\]/\"approach_axis\": [0, 0, "
                         "-1]/' " +
                         src + ".hand.json > " + dir + "/panda.hand.json")
                            .c_str()),
            0);
  const HandModel reversed = HandModel::load(dir + "/panda.urdf");
  ASSERT_EQ(reversed.approachAxis().z(), -1.0);
  BuildOptions o = smallBuild(2);
  o.max_trials = 200;
  const BuildResult r = buildMap(box(), reversed, o);
  EXPECT_EQ(r.status, BuildStatus::kNoGrasps);
  EXPECT_EQ(std::string(toString(r.status)), "no_grasps");
  EXPECT_EQ(r.map.grasps.size(), 0u);
  EXPECT_NE(r.message.find("no grasp stored after 200 trials: "), std::string::npos) << r.message;
  // The dominant outcome is named with its share, and what to check.
  std::string dominant;
  std::uint64_t most = 0;
  for (const auto& [name, count] : r.map.sampling.outcomes)
    if (count > most) {
      most = count;
      dominant = name;
    }
  EXPECT_NE(r.message.find("% ended " + dominant + "; "), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("approach_axis"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("Units: the object is 0.12 m across"), std::string::npos) << r.message;
}

TEST(MapBuilderTest, MillimetreObjectIsRefusedBeforeTheBuild) {
  // A 9 cm box written in millimetres and read as metres: 90 m across (below the loader's
  // absolute limit of 100 m, far beyond the hand).
  const ObjectModel mm = ObjectModel::fromMesh(testing::makeBox(40, 50, 90), "box_mm");
  try {
    buildMap(mm, panda(), smallBuild(1));
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("object 'box_mm' is too large for the hand: the object is 90 m across "
                       "(bounding box 40 x 50 x 90 m), 752 times the 0.12 m reach of hand"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("is the file in millimetres? scale 0.001 (--scale 0.001) makes it 0.09 m "
                       "across (in centimetres: --scale 0.01, 0.9 m; in inches: --scale 0.0254, "
                       "2.29 m)"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("--allow-size"), std::string::npos) << msg;
  }
  const ObjectModel tiny = ObjectModel::fromMesh(testing::makeBox(4e-5, 5e-5, 1.2e-4), "box_um");
  try {
    buildMap(tiny, panda(), smallBuild(1));
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("object 'box_um' is too small for the hand: the object is 0.00012 m across"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("its thinnest finger link is 0.012 m"), std::string::npos) << msg;
    EXPECT_NE(msg.find("check the scale (--scale"), std::string::npos) << msg;
  }
  // --allow-size (check_size = false) builds them anyway: here the tiny box, 20 trials.
  BuildOptions allow = smallBuild(1);
  allow.check_size = false;
  allow.max_trials = 20;
  EXPECT_NO_THROW(buildMap(tiny, panda(), allow));
}

TEST(MapBuilderTest, SizeCheckKnowsTheHand) {
  // 20 times the reach is the limit; the thinnest finger link the lower one.
  const HandModel hand = panda();
  const double reach = hand.reach();
  EXPECT_NEAR(thinnestFingerLink(hand), 0.012, 1e-12);
  const double big = 19.0 * reach, bigger = 21.0 * reach;
  EXPECT_TRUE(checkObjectSize(ObjectModel::fromMesh(testing::makeBox(big, 0.05, 0.05), "b"), hand)
                  .problem.empty());
  EXPECT_TRUE(
      checkObjectSize(ObjectModel::fromMesh(testing::makeBox(bigger, 0.05, 0.05), "b"), hand)
          .too_large);
  EXPECT_TRUE(
      checkObjectSize(ObjectModel::fromMesh(testing::makeBox(0.013, 0.013, 0.013), "s"), hand)
          .problem.empty());
  EXPECT_TRUE(
      checkObjectSize(ObjectModel::fromMesh(testing::makeBox(0.011, 0.011, 0.011), "s"), hand)
          .too_small);
}

TEST(MapBuilderTest, NoGraspMessageNamesTheSizeFirstWhenTheObjectDwarfsTheHand) {
  // A 1.2 m box: 10 times the panda's reach, allowed by the size check, no grasp in 5 trials.
  const ObjectModel big = ObjectModel::fromMesh(testing::makeBox(1.2, 1.2, 1.2), "big");
  BuildOptions o = smallBuild(1);
  o.max_trials = 5;
  o.cluster = false;
  const BuildResult r = buildMap(big, panda(), o);
  ASSERT_EQ(r.status, BuildStatus::kNoGrasps) << r.message;
  EXPECT_NE(r.message.find("no grasp stored after 5 trials: first suspect, the size: the object "
                           "is 1.2 m across"),
            std::string::npos)
      << r.message;
  EXPECT_NE(r.message.find("is the file in "), std::string::npos) << r.message;
  EXPECT_NE(r.message.find(". Then: "), std::string::npos) << r.message;
}

TEST(MapBuilderTest, StopFlagInterrupts) {
  std::atomic<bool> stop{true};
  BuildControl control;
  control.stop = &stop;
  const BuildResult r = buildMap(box(), panda(), smallBuild(2), control);
  EXPECT_EQ(r.status, BuildStatus::kInterrupted);
  EXPECT_EQ(r.map.sampling.trials, 0u);
  EXPECT_EQ(r.map.grasps.size(), 0u);
}

TEST(MapBuilderTest, ProgressIsReported) {
  int calls = 0;
  BuildProgress last;
  BuildControl control;
  control.progress = [&](const BuildProgress& p) {
    ++calls;
    EXPECT_GE(p.trials_done, last.trials_done);
    last = p;
  };
  control.interval_seconds = 0.001;
  // Mixed: its ~150 trials outlast the interval (the panda's default, antipodal_palm, stores
  // the grasps in a handful).
  BuildOptions o = smallBuild(2);
  o.sampler.kind = SamplerKind::kMixed;
  buildMap(box(), panda(), o, control);
  EXPECT_GE(calls, 1);
  EXPECT_EQ(last.valid_target, kValid);
  EXPECT_GE(last.valid_found, kValid);
}

TEST(MapBuilderTest, ExceptionFromTheProgressCallbackReachesTheCaller) {
  BuildControl control;
  control.progress = [](const BuildProgress&) { throw Error("callback failed"); };
  control.interval_seconds = 0.001;
  EXPECT_THROW(buildMap(box(), panda(), smallBuild(2), control), Error);
  control.interval_seconds = 0.0;
  EXPECT_TRUE(testing::throwsError([&] { buildMap(box(), panda(), smallBuild(2), control); },
                                   {"interval_seconds must be positive"}));
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
  // Link names: contact_links readable without the hand model, from C++ and from h5py.
  std::vector<std::string> links;
  for (const HandLink& l : panda().links()) links.push_back(l.name);
  EXPECT_EQ(back.hand.link_names, links);
  ASSERT_FALSE(back.grasps.contact_links.empty());
  const std::string script = ::testing::TempDir() + "links_" + std::to_string(::getpid()) + ".py";
  {
    std::ofstream py(script);
    py << "import h5py, sys\n"
          "f = h5py.File(sys.argv[1], 'r')\n"
          "links = f['hand/link_names'].asstr()[()]\n"
          "print(' '.join(links[k] for k in f['grasps/contact_links'][()][:3]))\n";
  }
  FILE* pipe = ::popen((std::string(TASKMAP_PYTHON) + " " + script + " " + path).c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  char buffer[512] = {};
  const std::string out = std::fgets(buffer, sizeof buffer, pipe) ? buffer : "";
  EXPECT_EQ(::pclose(pipe), 0);
  std::string expected;
  for (std::size_t i = 0; i < 3 && i < back.grasps.contact_links.size(); ++i)
    expected += (i ? " " : "") + links[static_cast<std::size_t>(back.grasps.contact_links[i])];
  EXPECT_EQ(out, expected + "\n");
  // A contact link beyond the stored names is refused.
  TaskMapData bad = back;
  bad.grasps.contact_links[0] = static_cast<std::int32_t>(links.size());
  EXPECT_THROW(bad.validate(), Error);
  std::remove(script.c_str());
  std::remove(path.c_str());
}

TEST(MapBuilderTest, InvalidOptionsAreRefused) {
  // Reset from a named default (GCC 12 warns, wrongly, about a temporary's vector members).
  const BuildOptions defaults;
  BuildOptions o;
  o.valid_target = 0;
  EXPECT_THROW(o.validate(), Error);
  o = defaults;
  o.threads = -1;
  EXPECT_THROW(o.validate(), Error);
  o = defaults;
  o.extra_params_json = "[1, 2]";
  EXPECT_THROW(o.validate(), Error);
  o = defaults;
  o.quality.friction = -1;
  EXPECT_THROW(o.validate(), Error);
  // Wrapped negatives and absurd budgets (issue 32).
  for (std::uint64_t n : {~std::uint64_t{0}, kMaxBuildCount + 1}) {
    o = defaults;
    o.max_trials = n;
    EXPECT_THROW(o.validate(), Error);
    o = defaults;
    o.valid_target = n;
    EXPECT_THROW(o.validate(), Error);
    o = defaults;
    o.block_size = n;
    EXPECT_THROW(o.validate(), Error);
  }
  EXPECT_NO_THROW(defaults.validate());
}

// A budget far beyond what a build runs costs memory only for the blocks that ran (the block
// table once took 8 bytes per 64 trials of the budget up front: 2 GB for 2^34 trials), and the
// largest budget neither wraps to zero blocks nor changes the map.
TEST(MapBuilderTest, HugeTrialBudgetCostsOnlyTheWorkDone) {
  BuildOptions o = smallBuild(2);
  const BuildResult small = buildMap(box(), panda(), o);
  o.max_trials = kMaxBuildCount;
  const BuildResult huge = buildMap(box(), panda(), o);
  ASSERT_EQ(huge.status, BuildStatus::kComplete) << huge.message;
  EXPECT_EQ(huge.map.sampling.trials, small.map.sampling.trials);
  ASSERT_EQ(huge.map.grasps.size(), small.map.grasps.size());
  EXPECT_TRUE((huge.map.grasps.pose.array() == small.map.grasps.pose.array()).all());
  EXPECT_EQ(huge.map.grasps.force_closure, small.map.grasps.force_closure);
}

}  // namespace
}  // namespace taskmap
