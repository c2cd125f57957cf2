// The build knobs (build_knobs.hpp): the one list both front ends declare, its checks and its
// translation into BuildOptions.
#include "taskmap/builder/build_knobs.hpp"

#include <gtest/gtest.h>

#include <cctype>
#include <set>
#include <string>

#include "error_matchers.hpp"

namespace taskmap {
namespace {

TEST(BuildKnobs, NamesAreUniqueSnakeCaseAndEveryKnobHasHelp) {
  BuildKnobs k;
  std::set<std::string> names;
  visitBuildKnobs(k, [&names](const KnobInfo& info, const auto&) {
    const std::string name = info.name;
    EXPECT_TRUE(names.insert(name).second) << name;
    for (char c : name) EXPECT_TRUE(std::islower(static_cast<unsigned char>(c)) || c == '_');
    EXPECT_GT(std::string(info.help).size(), 10u) << name;
  });
  EXPECT_EQ(names.size(), 22u);
  EXPECT_EQ(knobName("cone_edges", KnobStyle::kCommandLine), "--cone-edges");
  EXPECT_EQ(knobName("cone_edges", KnobStyle::kPython), "cone_edges");
}

TEST(BuildKnobs, DefaultsGiveTheDefaultBuildOptions) {
  const BuildOptions o = buildOptionsOf(BuildKnobs{}, KnobStyle::kCommandLine);
  const BuildOptions d;
  EXPECT_EQ(o.sampler.kind, d.sampler.kind);
  EXPECT_FALSE(o.sampler.kind.has_value());  // the hand's: antipodal_palm for jaws, else mixed
  EXPECT_EQ(o.valid_target, d.valid_target);
  EXPECT_EQ(o.max_trials, d.max_trials);
  EXPECT_EQ(o.seed, d.seed);
  EXPECT_EQ(o.quality.friction, d.quality.friction);
  EXPECT_EQ(o.quality.cone_edges, d.quality.cone_edges);
  EXPECT_EQ(o.quality.volume, d.quality.volume);
  EXPECT_EQ(o.quality.contacts_per_link, d.quality.contacts_per_link);
  EXPECT_EQ(o.stored, d.stored);
  EXPECT_EQ(o.cluster, d.cluster);
  EXPECT_EQ(o.hold_filter.enabled, d.hold_filter.enabled);
  EXPECT_EQ(o.check_size, d.check_size);
  EXPECT_FALSE(o.simulation.grasp_mode.has_value());
  EXPECT_LT(o.simulation.standoff, 0.0);
  EXPECT_EQ(holdValidationOf(BuildKnobs{}, KnobStyle::kPython), HoldValidation::kOff);
  // The front ends' one difference from the library: grasps are tested in physics, robustly.
  EXPECT_EQ(d.hold_test, BuildHoldTest::kOff);
  EXPECT_EQ(o.hold_test, BuildHoldTest::kRobust);
}

TEST(BuildKnobs, EachKnobReachesItsOption) {
  BuildKnobs k;
  k.sampler = "antipodal";
  k.valid = 7;
  k.trials = 99;
  k.seed = 5;
  k.threads = 3;
  k.friction = 0.8;
  k.cone_edges = 6;
  k.volume = "always";
  k.contacts_per_link = 4;
  k.grasp = "fingertip";
  k.standoff = 0.01;
  k.allow_size = k.keep_invalid = k.no_cluster = k.hold_filter = true;
  const BuildOptions o = buildOptionsOf(k, KnobStyle::kPython);
  EXPECT_EQ(o.sampler.kind, SamplerKind::kAntipodal);
  EXPECT_EQ(o.valid_target, 7u);
  EXPECT_EQ(o.max_trials, 99u);
  EXPECT_EQ(o.seed, 5u);
  EXPECT_EQ(o.threads, 3);
  EXPECT_EQ(o.quality.friction, 0.8);
  EXPECT_EQ(o.quality.cone_edges, 6);
  EXPECT_EQ(o.quality.volume, VolumeMode::kAlways);
  EXPECT_EQ(o.quality.contacts_per_link, 4);
  EXPECT_EQ(o.simulation.grasp_mode, GraspMode::kFingertip);
  EXPECT_EQ(o.simulation.standoff, 0.01);
  EXPECT_EQ(o.stored, StoredGrasps::kAllCompleted);
  EXPECT_FALSE(o.cluster);
  EXPECT_TRUE(o.hold_filter.enabled);
  EXPECT_FALSE(o.check_size);
  EXPECT_EQ(buildOptionsOf(k, KnobStyle::kPython).hold_test_options.hold.integrator,
            HoldTestOptions::Integrator::kImplicit);
  k.integrator = "implicitfast";
  EXPECT_EQ(buildOptionsOf(k, KnobStyle::kPython).hold_test_options.hold.integrator,
            HoldTestOptions::Integrator::kImplicitFast);
  k.hold_test = "nominal";
  EXPECT_EQ(buildOptionsOf(k, KnobStyle::kPython).hold_test, BuildHoldTest::kNominal);
  k.hold_test = "off";
  EXPECT_EQ(buildOptionsOf(k, KnobStyle::kPython).hold_test, BuildHoldTest::kOff);
  k.validate = true;
  EXPECT_EQ(holdValidationOf(k, KnobStyle::kPython), HoldValidation::kLabel);
  k.keep_holding = true;
  EXPECT_EQ(holdValidationOf(k, KnobStyle::kPython), HoldValidation::kKeepHolding);
}

TEST(BuildKnobs, ClosingCheckModesAndTheEarlySettings) {
  BuildKnobs k;
  EXPECT_EQ(buildOptionsOf(k, KnobStyle::kPython).closing_check.mode, ClosingCheckMode::kOff);
  k.closing_check = "pushes";
  const ClosingCheckOptions full = buildOptionsOf(k, KnobStyle::kPython).closing_check;
  EXPECT_EQ(full.mode, ClosingCheckMode::kPushes);
  EXPECT_EQ(full.rest_speed, ClosingCheckOptions{}.rest_speed);  // the full pushes
  k.closing_check = "pushes_early";
  const ClosingCheckOptions early = buildOptionsOf(k, KnobStyle::kPython).closing_check;
  const ClosingCheckOptions expected = ClosingCheckOptions::earlyVerdict();
  EXPECT_EQ(early.mode, ClosingCheckMode::kPushes);
  EXPECT_GT(early.rest_speed, 0.0);
  EXPECT_EQ(early.rest_speed, expected.rest_speed);
  EXPECT_EQ(early.settle_erp, expected.settle_erp);
}

TEST(BuildKnobs, ErrorsNameTheKnobAsTheFrontEndSpellsIt) {
  BuildKnobs k;
  k.cone_edges = 2;
  EXPECT_TRUE(testing::throwsError([&] { checkBuildKnobs(k, KnobStyle::kCommandLine); },
                                   {"--cone-edges must be within [3, 64] (got 2)"}));
  EXPECT_TRUE(testing::throwsError([&] { checkBuildKnobs(k, KnobStyle::kPython); },
                                   {"cone_edges must be within [3, 64] (got 2)"}));
  k = BuildKnobs{};
  k.valid = 0;
  EXPECT_TRUE(testing::throwsError([&] { buildOptionsOf(k, KnobStyle::kPython); },
                                   {"valid must be positive (got 0)"}));
  k = BuildKnobs{};
  k.sampler = "grid";
  EXPECT_TRUE(testing::throwsError([&] { buildOptionsOf(k, KnobStyle::kPython); },
                                   {"sampler must be one of volume, surface, mixed, antipodal, "
                                    "enclose, antipodal_palm, palm_enclose (got \"grid\")"}));
  k = BuildKnobs{};
  k.friction = -0.1;
  EXPECT_TRUE(testing::throwsError([&] { buildOptionsOf(k, KnobStyle::kCommandLine); },
                                   {"--friction must be >= 0"}));
  k = BuildKnobs{};
  k.standoff = 0.7;
  EXPECT_TRUE(testing::throwsError([&] { buildOptionsOf(k, KnobStyle::kPython); },
                                   {"standoff must be within [0, 0.5] (got 0.7)"}));
  k = BuildKnobs{};
  k.keep_holding = true;
  EXPECT_TRUE(testing::throwsError([&] { holdValidationOf(k, KnobStyle::kCommandLine); },
                                   {"--keep-holding needs --validate"}));
  EXPECT_TRUE(testing::throwsError([&] { holdValidationOf(k, KnobStyle::kPython); },
                                   {"keep_holding needs validate"}));
  // Labelling after the build is for builds that did not test their grasps already.
  k = BuildKnobs{};
  k.validate = true;
  EXPECT_TRUE(testing::throwsError([&] { holdValidationOf(k, KnobStyle::kCommandLine); },
                                   {"--validate labels", "--hold-test robust", "--hold-test off"}));
  k = BuildKnobs{};
  k.hold_test = "strict";
  EXPECT_TRUE(testing::throwsError([&] { buildOptionsOf(k, KnobStyle::kPython); },
                                   {"hold_test must be one of robust, nominal, off"}));
}

}  // namespace
}  // namespace taskmap
