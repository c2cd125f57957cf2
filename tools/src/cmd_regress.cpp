// `taskmap regress [--update]`: the regression suite on reference objects (tests/regression/).
#include <iostream>
#include <memory>

#include "command.hpp"
#include "taskmap/builder/regression_suite.hpp"

namespace taskmap::cli {
namespace {

int run(const RegressionSuiteOptions& options) {
  const RegressionSuiteResult result = runRegressionSuite(options, [](const RegressionCaseRun& c) {
    std::cout << regressionCaseText(c) << std::flush;
  });
  if (options.update) {
    std::cout << "\nregress: golden files updated for " << result.cases.size()
              << " case(s); review `git diff " << result.golden_dir << "`\n";
    return 0;
  }
  std::cout << "\nregress: " << result.cases.size() << " case(s), " << result.failures
            << " statistic(s) failed\n";
  return result.failures ? 1 : 0;
}

const CommandRegistrar kRegistrar(
    "regress", "Build the reference maps and compare them with the golden statistics",
    [](CLI::App& app) {
      auto args = std::make_shared<RegressionSuiteOptions>();
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
