// The map-building pipeline: deterministic parallel trials in fixed blocks, then assembleMap.
#include "taskmap/builder/map_builder.hpp"

#include <cmath>
#include <ctime>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "build_diagnosis.hpp"
#include "taskmap/builder/sampler_choice.hpp"
#include "taskmap/builder/size_check.hpp"
#include "taskmap/builder/trial_block.hpp"
#include "taskmap/core/error.hpp"
#include "trial_pool.hpp"

namespace taskmap {

void BuildOptions::validate() const {
  sampler.validate();
  simulation.validate();
  quality.validate();
  hold_filter.validate();
  closing_check.validate();
  if (hold_test != BuildHoldTest::kOff) hold_test_options.validate();
  if (!(min_squeeze_force >= 0.0) || !std::isfinite(min_squeeze_force))
    throw Error("min_squeeze_force must be finite and >= 0 (N; 0 turns the test off)");
  if (valid_target < 1) throw Error("valid must be at least 1");
  if (max_trials < 1) throw Error("trials must be at least 1");
  if (valid_target > kMaxBuildCount)
    throw Error("valid must be at most 10^15 (got " + std::to_string(valid_target) + ")");
  if (max_trials > kMaxBuildCount)
    throw Error("trials must be at most 10^15 (got " + std::to_string(max_trials) + ")");
  if (block_size > kMaxBuildCount)
    throw Error("block_size must be at most 10^15 (got " + std::to_string(block_size) + ")");
  if (threads < 0) throw Error("threads must be 0 (all cores) or positive");
  if (threads > 1024) throw Error("threads must be at most 1024");
  if (block_size < 1) throw Error("block_size must be at least 1");
  try {
    if (!nlohmann::json::parse(extra_params_json).is_object())
      throw Error("extra_params_json must be a JSON object");
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("extra_params_json is not valid JSON: ") + e.what());
  }
  if (cluster) {
    ClusteringOptions c = clustering;
    c.rotation_scale = kDefaultRotationScale;  // replaced by the hand's
    c.validate();
  }
}

QualityOptions buildQualityDefaults() {
  QualityOptions o;
  o.volume = VolumeMode::kNever;
  return o;
}

const char* toString(BuildHoldTest test) {
  switch (test) {
    case BuildHoldTest::kOff:
      return "off";
    case BuildHoldTest::kNominal:
      return "nominal";
    case BuildHoldTest::kRobust:
      return "robust";
  }
  return "off";
}

BuildHoldTest buildHoldTestFromString(const std::string& name) {
  for (BuildHoldTest t : {BuildHoldTest::kOff, BuildHoldTest::kNominal, BuildHoldTest::kRobust})
    if (name == toString(t)) return t;
  throw Error("hold test '" + name + "' is unknown; use 'robust', 'nominal' or 'off'");
}

const char* toString(BuildStatus status) {
  switch (status) {
    case BuildStatus::kComplete:
      return "complete";
    case BuildStatus::kTrialBudgetExhausted:
      return "trial_budget_exhausted";
    case BuildStatus::kInterrupted:
      return "interrupted";
    case BuildStatus::kNoGrasps:
      return "no_grasps";
  }
  return "complete";
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

int buildThreadCount(int threads) {
  return detail::threadCount(threads);
}

BuildResult buildMap(const ObjectModel& object, const HandModel& hand,
                     const BuildOptions& requested, const BuildControl& control) {
  requested.validate();
  control.validate();
  if (requested.check_size) requirePlausibleSize(object, hand);
  const auto t_start = detail::Clock::now();
  BuildTiming timing;
  const SamplerChoice choice = chooseSampler(object, hand, requested);
  BuildOptions options = requested;
  options.sampler.kind = choice.kind;
  const int threads = detail::threadCount(options.threads);
  const Sampler sampler(object, detail::samplerOptionsFor(options, hand));
  const GraspSimulator simulator(object, hand, options.simulation);
  const std::unique_ptr<const ClosingChecker> closing =
      detail::makeClosingChecker(object, hand, options);
  const std::unique_ptr<const RobustHoldTester> hold =
      detail::makeHoldTester(object, hand, options);
  const MassProperties& mp = object.massProperties();
  timing.setup_seconds = detail::secondsSince(t_start);

  detail::Scheduler scheduler(0, options.max_trials, detail::blockSize(options),
                              options.valid_target);
  const detail::TrialPoolSetup setup{
      sampler,      simulator,         closing.get(),           hold.get(),
      options,      mp.center_of_mass, mp.torque_scale,         threads,
      control.stop, control.progress,  control.interval_seconds};
  detail::runTrialPool(setup, scheduler, timing);
  const bool interrupted = control.stopRequested() && !scheduler.done();
  BuildResult result =
      assembleMap(object, hand, options, scheduler.takePrefixBlocks(), interrupted, timing);
  result.timing.wall_seconds = detail::secondsSince(t_start);
  result.sampler_choice = choice;
  return result;
}

}  // namespace taskmap
