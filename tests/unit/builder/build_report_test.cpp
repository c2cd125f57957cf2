// builder/build_report.hpp: the texts `taskmap build`, `dataset` and `taskmap-mpi` print.
#include "taskmap/builder/build_report.hpp"

#include <string>

#include <gtest/gtest.h>

namespace taskmap {
namespace {

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(BuildReportTest, ClockStringRoundsAndRefusesWhatIsUnknown) {
  EXPECT_EQ(clockString(0.0), "00:00:00");
  EXPECT_EQ(clockString(3661.4), "01:01:01");
  EXPECT_EQ(clockString(59.6), "00:01:00");
  EXPECT_EQ(clockString(-1.0), "--:--:--");
  EXPECT_EQ(clockString(1e9), "--:--:--");
}

TEST(BuildReportTest, ProgressIsTheLargerShareOfValidGraspsAndTrials) {
  BuildProgress p;
  p.valid_target = 100;
  p.valid_found = 25;
  p.max_trials = 1000;
  p.trials_done = 500;
  p.elapsed_seconds = 10.0;
  EXPECT_DOUBLE_EQ(buildProgressFraction(p), 0.5);
  const std::string bar = buildProgressLine(p, "taskmap build", true);
  EXPECT_EQ(bar.rfind("\r[###############---------------]  50%", 0), 0u) << bar;
  EXPECT_TRUE(has(bar, "valid 25/100")) << bar;
  EXPECT_TRUE(has(bar, "50 trials/s")) << bar;
  EXPECT_TRUE(has(bar, "ETA 00:00:10")) << bar;
  const std::string log = buildProgressLine(p, "taskmap build", false);
  EXPECT_EQ(log,
            "taskmap build: 00:00:10 elapsed, 500 trials, 25/100 valid, 50 trials/s, ETA "
            "00:00:10\n");
  p.valid_found = 300;  // more than asked: counted as the target
  EXPECT_DOUBLE_EQ(buildProgressFraction(p), 1.0);
}

TEST(BuildReportTest, SummaryNamesOutcomesStoredGraspsTimesAndOutput) {
  BuildResult r;
  r.status = BuildStatus::kTrialBudgetExhausted;
  r.message = "3 of 10 valid grasps";
  r.map.object.name = "cylinder";
  r.map.hand.name = "barrett";
  r.map.sampling.sampler = "mixed";
  r.map.sampling.outcomes = {{"ok", 3}, {"no_contact", 7}};
  r.timing.sampling_seconds = 1.0;
  r.timing.simulation_seconds = 2.0;
  r.timing.quality_seconds = 1.0;
  const std::string text = buildSummaryText("taskmap build", r, 0.5, "2", "out.h5");
  EXPECT_TRUE(has(text, "object    cylinder")) << text;
  EXPECT_TRUE(has(text, "hand barrett, sampler mixed\n")) << text;  // the one that ran
  EXPECT_TRUE(has(text, "no_contact 7")) << text;
  EXPECT_TRUE(has(text, "simulation 50.0%")) << text;
  EXPECT_TRUE(has(text, "wrote     out.h5\n")) << text;
  EXPECT_FALSE(has(text, "closing")) << text;  // no closing check ran
  EXPECT_TRUE(has(buildBudgetWarning("taskmap build", r), "raise --trials"));
  r.status = BuildStatus::kComplete;
  EXPECT_EQ(buildBudgetWarning("taskmap build", r), "");
  // A build that runs mixed because palm_enclose cannot place the hand says so.
  r.sampler_choice.enclose_refused = true;
  const std::string refused = buildSummaryText("taskmap build", r, 0.5, "2", "out.h5");
  EXPECT_TRUE(has(refused, "sampler mixed (palm_enclose cannot place the hand on this object)\n"))
      << refused;
}

TEST(BuildReportTest, HoldLabelsLineAndKeepHolding) {
  EXPECT_EQ(holdLabelsText("x", std::nullopt, true), "");
  HoldLabels h;
  h.tested = 8;
  h.holding = 6;
  h.cpu_seconds = 2.0;
  h.before = 8;
  h.kept = 6;
  EXPECT_EQ(holdLabelsText("taskmap build", h, false),
            "taskmap build: physics validation: 6 of 8 grasps hold (75.0 %), 4.0 grasps per "
            "CPU-second\n");
  EXPECT_TRUE(has(holdLabelsText("taskmap build", h, true), "--keep-holding: kept 6 of 8"));
}

}  // namespace
}  // namespace taskmap
