// taskmap build: sample, simulate and score grasp trials on all cores and write
// a task map.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "build_command.hpp"
#include "command.hpp"
#include "run_lock.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/builder/size_check.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/meshes/object_size.hpp"

namespace taskmap::cli {
namespace {

std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free, "signal handler needs a lock-free flag");

extern "C" void onStopSignal(int sig) {
  g_stop.store(true);
  // A second Ctrl-C kills at once (the output path is still safe: written via
  // rename).
  std::signal(sig, SIG_DFL);
}

void runBuild(const BuildArgs& args) {
  const BuildPlan plan = planBuild(args);
  // One build at a time per output: a second one refuses with the holder's PID.
  const RunLock lock(args.output + ".lock", "output '" + args.output + "'");
  const BuildOptions& options = plan.options;
  const std::string& hand_path = plan.hand_urdf;

  // The hand first: its warnings, and the size check while the mesh loads (before its repair).
  const HandModel hand = HandModel::load(hand_path);
  checkGraspOptions(args, options, hand, hand_path);
  const bool hand_warned = printHandWarnings("taskmap build", hand);
  const ObjectModel object = [&] {
    const ScopedLoadBoundsCheck size_check(
        options.check_size
            ? sizeCheckOnLoad(hand, std::filesystem::path(args.object).stem().string(), args.scale)
            : nullptr);
    return ObjectModel::load(args.object, meshLoadOptions(args));
  }();

  g_stop.store(false);
  struct sigaction action {};
  action.sa_handler = onStopSignal;
  sigemptyset(&action.sa_mask);
  struct sigaction old_int {
  }, old_term{};
  sigaction(SIGINT, &action, &old_int);
  sigaction(SIGTERM, &action, &old_term);

  ProgressPrinter printer("taskmap build", ::isatty(STDERR_FILENO) != 0 || args.progress,
                          args.quiet);
  BuildResult result;
  try {
    result = buildMap(
        object, hand, options, [&printer](const BuildProgress& p) { printer(p); }, &g_stop);
  } catch (...) {
    printer.finish();
    sigaction(SIGINT, &old_int, nullptr);
    sigaction(SIGTERM, &old_term, nullptr);
    throw;
  }
  printer.finish();
  if (result.status == BuildStatus::kInterrupted) {
    sigaction(SIGINT, &old_int, nullptr);
    sigaction(SIGTERM, &old_term, nullptr);
    std::cerr << "taskmap build: " << result.message << "; nothing written to '" << args.output
              << "'\n";
    exitCode() = 130;
    return;
  }
  if (result.status == BuildStatus::kNoGrasps) {
    sigaction(SIGINT, &old_int, nullptr);
    sigaction(SIGTERM, &old_term, nullptr);
    std::cerr << "taskmap build: error: " << result.message
              << (hand_warned ? "; and the hand's warning above: the set-up it names cannot grasp"
                              : "")
              << "; nothing written to '" << args.output << "'\n";
    exitCode() = 3;
    return;
  }
  if (args.timestamp) result.map.created_utc = mapCreationTime(true);
  validateIfAsked(args, hand, &result.map, "taskmap build");
  const auto t_write = std::chrono::steady_clock::now();
  writeMap(args.output,
           result.map);  // signals stay caught: the write is never cut short
  const double write_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_write).count();
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);

  const int threads = buildThreadCount(options.threads);
  printBuildSummary("taskmap build", args, result, write_seconds,
                    std::to_string(threads) + " (not stored: the map does not depend on it)");
}

const CommandRegistrar kRegistrar("build", [](CLI::App& app) {
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
