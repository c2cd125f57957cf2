// `taskmap regress [--update]`: the regression suite on reference objects (tests/regression/).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>

#include "command.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/inspect/regression.hpp"

namespace taskmap::cli {
namespace {

namespace fs = std::filesystem;

struct RegressArgs {
  std::string cases;       // default: <data dir>/regression/cases.json
  std::string golden_dir;  // default: <cases dir>/golden
  std::vector<std::string> only;
  bool update = false;
  int threads = 0;
  double friction = -1.0;  // < 0: the default of QualityOptions
};

void printTable(const std::vector<ComparisonRow>& rows, const std::string& object,
                const std::string& hand) {
  std::cout << std::left << std::setw(10) << "object" << std::setw(17) << "hand" << std::setw(30)
            << "statistic" << std::setw(34) << "golden" << std::setw(34) << "now"
            << "verdict\n";
  for (const auto& r : rows) {
    std::cout << std::left << std::setw(10) << object << std::setw(17) << hand << std::setw(30)
              << r.statistic << std::setw(34) << r.golden << std::setw(34) << r.now
              << (r.pass ? "ok" : "FAIL") << "\n";
  }
}

int run(const RegressArgs& args) {
  const fs::path cases_path =
      fs::absolute(args.cases.empty() ? fs::path(dataDir()) / "regression" / "cases.json"
                                      : fs::path(args.cases));
  const fs::path root = cases_path.parent_path();
  const fs::path golden_dir = args.golden_dir.empty() ? root / "golden" : fs::path(args.golden_dir);
  const auto cases = readCases(cases_path.string());
  int failures = 0, ran = 0;
  for (const auto& c : cases) {
    if (!args.only.empty() &&
        std::find(args.only.begin(), args.only.end(), c.name) == args.only.end()) {
      continue;
    }
    ++ran;
    const ObjectModel object = ObjectModel::load((root / c.object).lexically_normal().string());
    const HandModel hand = HandModel::load(
        (root / c.hand).lexically_normal().string(),
        c.sidecar.empty() ? std::string() : (root / c.sidecar).lexically_normal().string());
    BuildOptions options;
    options.sampler.kind = samplerKindFromString(c.sampler);
    options.seed = c.seed;
    options.max_trials = c.trials;
    options.valid_target = c.trials;  // a fixed budget: every trial runs
    options.threads = args.threads;
    if (args.friction >= 0.0) options.quality.friction = args.friction;
    const BuildResult built = buildMap(object, hand, options);
    const MapStatistics now = computeStatistics(built.map);
    const fs::path golden_path = golden_dir / (c.name + ".json");
    std::cout << "\n== " << c.name << ": " << object.name() << " with " << hand.name() << ", "
              << c.trials << " trials, seed " << c.seed << ", sampler " << c.sampler << " ("
              << std::fixed << std::setprecision(1) << built.timing.wall_seconds << " s)\n";
    if (args.update) {
      fs::create_directories(golden_dir);
      writeFileAtomically(golden_path.string(), goldenFileText(now, c),
                          "cannot write golden file '" + golden_path.string() + "'");
      std::cout << "updated " << golden_path.string() << "\n";
      continue;
    }
    const std::optional<MapStatistics> golden = readGoldenFile(golden_path.string());
    if (!golden) {
      std::cout << golden_path.string() << ": no golden file; run `taskmap regress --update`\n";
      ++failures;
      continue;
    }
    const RegressionResult result = compareWithGolden(c.name, *golden, now);
    printTable(result.rows, object.name(), hand.name());
    for (const auto& r : result.rows) failures += r.pass ? 0 : 1;
  }
  if (ran == 0) throw Error("no regression case matched; see " + cases_path.string());
  if (args.update) {
    std::cout << "\nregress: golden files updated for " << ran << " case(s); review `git diff "
              << golden_dir.string() << "`\n";
    return 0;
  }
  std::cout << "\nregress: " << ran << " case(s), " << failures << " statistic(s) failed\n";
  return failures ? 1 : 0;
}

const CommandRegistrar kRegistrar("regress", [](CLI::App& app) {
  auto args = std::make_shared<RegressArgs>();
  auto* cmd = app.add_subcommand(
      "regress", "Build the reference maps and compare them with golden statistics");
  cmd->add_option("--cases", args->cases,
                  "Case list (JSON; default <data dir>/regression/cases.json); paths in it are "
                  "relative to its folder")
      ->capture_default_str();
  cmd->add_option("--golden", args->golden_dir,
                  "Folder of golden files (default: <cases folder>/golden)");
  cmd->add_option("--only", args->only, "Run only these cases (by name)");
  cmd->add_flag("--update", args->update, "Rewrite the golden files from this build");
  cmd->add_option("--threads", args->threads,
                  "Worker threads (0: all cores); results do not depend on it");
  cmd->add_option("--friction", args->friction,
                  "Override the friction coefficient (to see the suite catch a change)");
  cmd->callback([args]() { exitCode() = run(*args); });
});

}  // namespace
}  // namespace taskmap::cli
