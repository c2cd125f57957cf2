// The regression suite (builder/regression_suite.hpp): build each reference case, compare its
// statistics with the golden file or rewrite it.
#include "taskmap/builder/regression_suite.hpp"

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "taskmap/builder/map_builder.hpp"
#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

/// Builds case c (paths relative to root) and compares or updates its golden file.
RegressionCaseRun runCase(const RegressionCase& c, const fs::path& root, const fs::path& golden_dir,
                          const RegressionSuiteOptions& options) {
  RegressionCaseRun run;
  run.spec = c;
  const ObjectModel object = ObjectModel::load((root / c.object).lexically_normal().string());
  const HandModel hand = HandModel::load(
      (root / c.hand).lexically_normal().string(),
      c.sidecar.empty() ? std::string() : (root / c.sidecar).lexically_normal().string());
  run.object = object.name();
  run.hand = hand.name();
  BuildOptions build;
  build.sampler.kind = samplerKindFromString(c.sampler);
  build.seed = c.seed;
  build.max_trials = c.trials;
  build.valid_target = c.trials;  // a fixed budget: every trial runs
  build.threads = options.threads;
  if (options.friction) build.quality.friction = *options.friction;
  const BuildResult built = buildMap(object, hand, build);
  run.wall_seconds = built.timing.wall_seconds;
  const MapStatistics now = computeStatistics(built.map);
  run.golden_path = (golden_dir / (c.name + ".json")).string();
  if (options.update) {
    fs::create_directories(golden_dir);
    writeFileAtomically(run.golden_path, goldenFileText(now, c),
                        "cannot write golden file '" + run.golden_path + "'");
    run.outcome = RegressionCaseRun::Outcome::kUpdated;
    return run;
  }
  const std::optional<MapStatistics> golden = readGoldenFile(run.golden_path);
  if (!golden) {
    run.outcome = RegressionCaseRun::Outcome::kNoGolden;
    run.failures = 1;
    return run;
  }
  run.comparison = compareWithGolden(c.name, *golden, now);
  for (const ComparisonRow& r : run.comparison.rows) run.failures += r.pass ? 0 : 1;
  return run;
}

}  // namespace

RegressionSuiteResult runRegressionSuite(
    const RegressionSuiteOptions& options,
    const std::function<void(const RegressionCaseRun&)>& on_case) {
  const fs::path cases_path =
      fs::absolute(options.cases.empty() ? fs::path(dataDir()) / "regression" / "cases.json"
                                         : fs::path(options.cases));
  const fs::path root = cases_path.parent_path();
  const fs::path golden_dir =
      options.golden_dir.empty() ? root / "golden" : fs::path(options.golden_dir);
  RegressionSuiteResult result;
  result.cases_path = cases_path.string();
  result.golden_dir = golden_dir.string();
  for (const RegressionCase& c : readCases(cases_path.string())) {
    if (!options.only.empty() &&
        std::find(options.only.begin(), options.only.end(), c.name) == options.only.end())
      continue;
    result.cases.push_back(runCase(c, root, golden_dir, options));
    result.failures += result.cases.back().failures;
    if (on_case) on_case(result.cases.back());
  }
  if (result.cases.empty()) throw Error("no regression case matched; see " + result.cases_path);
  return result;
}

std::string regressionCaseText(const RegressionCaseRun& run) {
  std::ostringstream os;
  const RegressionCase& c = run.spec;
  os << "\n== " << c.name << ": " << run.object << " with " << run.hand << ", " << c.trials
     << " trials, seed " << c.seed << ", sampler " << c.sampler << " (" << std::fixed
     << std::setprecision(1) << run.wall_seconds << " s)\n";
  if (run.outcome == RegressionCaseRun::Outcome::kUpdated)
    return os.str() + "updated " + run.golden_path + "\n";
  if (run.outcome == RegressionCaseRun::Outcome::kNoGolden)
    return os.str() + run.golden_path + ": no golden file; run `taskmap regress --update`\n";
  os << std::left << std::setw(10) << "object" << std::setw(17) << "hand" << std::setw(30)
     << "statistic" << std::setw(34) << "golden" << std::setw(34) << "now"
     << "verdict\n";
  for (const ComparisonRow& r : run.comparison.rows)
    os << std::left << std::setw(10) << run.object << std::setw(17) << run.hand << std::setw(30)
       << r.statistic << std::setw(34) << r.golden << std::setw(34) << r.now
       << (r.pass ? "ok" : "FAIL") << "\n";
  return os.str();
}

}  // namespace taskmap
