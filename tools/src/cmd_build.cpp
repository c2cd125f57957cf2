// taskmap build: sample, simulate and score grasp trials on all cores and write
// a task map.
#include <unistd.h>

#include <iostream>
#include <memory>

#include "build_command.hpp"
#include "command.hpp"
#include "taskmap/core/stop_signals.hpp"

namespace taskmap::cli {
namespace {

void runBuild(const BuildArgs& args) {
  // Plan, the output's lock (a second build refuses with the holder's PID), the hand.
  MapFileBuild build(fileBuildOptions(args));
  // The hand's warnings before the trials, then the object (the size check while it loads).
  const bool hand_warned = printHandWarnings("taskmap build", build.hand());
  build.loadObject();

  ProgressPrinter printer("taskmap build", ::isatty(STDERR_FILENO) != 0 || args.progress,
                          args.quiet);
  BuildControl control;
  control.progress = [&printer](const BuildProgress& p) { printer(p); };
  control.stop = StopSignals::flag();
  FileBuildResult result;
  {
    const StopSignals signals;  // also while writing: the write is never cut short
    try {
      result = build.run(control);
    } catch (...) {
      printer.finish();
      throw;
    }
    printer.finish();
  }
  const BuildResult& built = result.build;
  if (built.status == BuildStatus::kInterrupted) {
    std::cerr << "taskmap build: " << built.message << "; nothing written to '" << args.output
              << "'\n";
    exitCode() = 130;
    return;
  }
  if (built.status == BuildStatus::kNoGrasps) {
    std::cerr << "taskmap build: error: " << built.message
              << (hand_warned ? "; and the hand's warning above: the set-up it names cannot grasp"
                              : "")
              << "; nothing written to '" << args.output << "'\n";
    exitCode() = 3;
    return;
  }
  printHoldLabels("taskmap build", result.validation, args.keep_holding, args.quiet);
  printBuildSummary(
      "taskmap build", args, built, result.write_seconds,
      std::to_string(result.threads) + " (not stored: the map does not depend on it)");
}

const CommandRegistrar kRegistrar(
    "build", "Build a task map: sample, simulate, score, test the grasps in physics, cluster",
    [](CLI::App& app) {
      auto args = std::make_shared<BuildArgs>();
      CLI::App* cmd =
          app.add_subcommand("build",
                             "Build a task map: sample initial hand poses, simulate each "
                             "grasp trial (retract, close, "
                             "squeeze), score force closure, cluster the grasps, and write "
                             "an HDF5 map "
                             "(mapstore/SCHEMA.md). The same command and seed give the same "
                             "map for any --threads.");
      addBuildOptions(*cmd, *args);
      cmd->callback([args]() { runBuild(*args); });
    });

}  // namespace
}  // namespace taskmap::cli
