// taskmap-mpi build: rank 0 hands out fixed blocks of trials on request (task_farm.hpp) and runs
// blocks itself on a second thread; every other rank runs the blocks it gets on the threaded
// trial pool and sends back the outcomes. Rank 0 applies buildMap's stop rule, keeps a checkpoint
// of finished blocks beside the output, assembles and writes the map (the same bytes as `taskmap
// build`).
#include "mpi_build.hpp"

#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>
#include <optional>

#include "build_command.hpp"
#include "mpi_common.hpp"
#include "task_farm.hpp"
#include "taskmap/builder/block_ledger.hpp"
#include "taskmap/builder/build_checkpoint.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/run_lock.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap::cli {
namespace {

// Everything of a build every rank has.
struct RankSetup {
  std::optional<RunLock> lock;  // rank 0's, on the output (the lock of `taskmap build`)
  FileBuildPlan plan;
  std::unique_ptr<ObjectModel> object;
  std::unique_ptr<HandModel> hand;
  std::unique_ptr<TrialRunner> runner;
};

// Rank 0's side of the farm: blocks by index from the ledger, results into the checkpoint.
FarmTasks buildTasks(RankSetup& setup, BlockLedger* ledger, BuildCheckpoint* checkpoint,
                     ProgressPrinter* printer, std::uint64_t block_trials,
                     std::uint64_t* simulated) {
  FarmTasks tasks;
  tasks.run = [&setup, block_trials](std::uint64_t b) {
    const std::uint64_t first = b * block_trials;
    const std::uint64_t last = std::min(first + block_trials, setup.plan.options.max_trials);
    TrialBlock block;
    setup.runner->run(first, last, &block);
    return encodeTrialBlock(block);
  };
  if (ledger == nullptr) return tasks;  // a worker rank only runs
  tasks.next = [ledger](std::uint64_t* b) { return ledger->next(b); };
  tasks.accept = [&setup, ledger, checkpoint, simulated](std::uint64_t b, std::string bytes) {
    TrialBlock block = decodeTrialBlock(bytes, setup.hand->jointNames().size(),
                                        "result of block " + std::to_string(b));
    *simulated += block.trials.size();
    checkpoint->append(block);
    if (!ledger->record(std::move(block)))
      throw Error("internal: block " + std::to_string(b) + " came back with other trials");
  };
  const auto t0 = std::chrono::steady_clock::now();
  tasks.tick = [&setup, ledger, printer, t0] {
    BuildProgress p;
    p.trials_done = ledger->trialsDone();
    p.valid_found = ledger->validFound();
    p.valid_target = setup.plan.options.valid_target;
    p.max_trials = setup.plan.options.max_trials;
    p.elapsed_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    p.blocks_done = ledger->blocksDone();
    p.blocks_total = ledger->blockCount();
    (*printer)(p);
  };
  return tasks;
}

// Rank 0 on SIGINT/SIGTERM (mpirun forwards Ctrl-C): one line saying the checkpoint stays,
// then the default action. Only async-signal-safe calls.
char g_stop_message[1024] = "";
extern "C" void onStopSignal(int sig) {
  const ssize_t ignored = ::write(STDERR_FILENO, g_stop_message, std::strlen(g_stop_message));
  (void)ignored;
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

void announceCheckpointOnStop(const std::string& checkpoint) {
  std::snprintf(g_stop_message, sizeof g_stop_message,
                "\ntaskmap-mpi build: stopped; no map written, finished blocks kept in '%s': "
                "the same command resumes from them\n",
                checkpoint.c_str());
  std::signal(SIGINT, onStopSignal);
  std::signal(SIGTERM, onStopSignal);
}

// Loads the inputs on this rank; every rank learns whether all succeeded.
bool setUp(const MpiWorld& world, const BuildArgs& args, RankSetup& setup) {
  std::string error;
  try {
    setup.plan = planFileBuild(fileBuildOptions(args));
    // One build at a time per output, MPI or not: a second one refuses with the holder's PID.
    if (world.rank == 0) setup.lock.emplace(args.output + ".lock", "output '" + args.output + "'");
    setup.object =
        std::make_unique<ObjectModel>(ObjectModel::load(args.object, meshLoadOptions(args)));
    setup.hand = std::make_unique<HandModel>(HandModel::load(setup.plan.hand_urdf));
    checkGraspOptions(setup.plan.options, *setup.hand, setup.plan.hand_urdf);
    if (world.rank == 0) printHandWarnings("taskmap-mpi build", *setup.hand);
    setup.runner = std::make_unique<TrialRunner>(*setup.object, *setup.hand, setup.plan.options);
  } catch (const std::exception& e) {
    error = e.what();
  }
  return agreeAllOk(world, error, "taskmap-mpi build");
}

// Stage CPU seconds and trials summed over the ranks (on rank 0).
BuildTiming sumTiming(const TrialRunner& runner) {
  const BuildTiming& t = runner.timing();
  double mine[4] = {t.sampling_seconds, t.simulation_seconds, t.quality_seconds,
                    static_cast<double>(t.trials_simulated)};
  double sum[4] = {0, 0, 0, 0};
  MPI_Reduce(mine, sum, 4, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
  BuildTiming out = t;
  out.sampling_seconds = sum[0];
  out.simulation_seconds = sum[1];
  out.quality_seconds = sum[2];
  out.trials_simulated = static_cast<std::uint64_t>(sum[3]);
  return out;
}

}  // namespace

int runMpiBuild(const MpiWorld& world, const BuildArgs& args, std::uint64_t block_trials) {
  const auto t_start = std::chrono::steady_clock::now();
  RankSetup setup;
  if (!setUp(world, args, setup)) return 1;
  if (world.rank != 0) {
    runFarm(world, buildTasks(setup, nullptr, nullptr, nullptr, block_trials, nullptr));
    sumTiming(*setup.runner);
    return 0;
  }
  const BuildOptions& options = setup.plan.options;
  BlockLedger ledger(options.max_trials, block_trials, options.valid_target);
  BuildCheckpoint checkpoint(args.output + ".ckpt",
                             buildIdentity(*setup.object, *setup.hand, options, block_trials),
                             setup.hand->jointNames().size());
  if (!checkpoint.loadNote().empty() && !args.quiet)
    std::cerr << "taskmap-mpi build: " << checkpoint.loadNote() << "\n";
  announceCheckpointOnStop(checkpoint.path());
  std::uint64_t resumed = 0;
  for (TrialBlock& b : checkpoint.takeLoaded()) resumed += ledger.record(std::move(b)) ? 1 : 0;
  ProgressPrinter printer("taskmap-mpi build", ::isatty(STDERR_FILENO) != 0 || args.progress,
                          args.quiet);
  std::uint64_t simulated = 0;
  runFarm(world, buildTasks(setup, &ledger, &checkpoint, &printer, block_trials, &simulated));
  printer.finish();
  BuildTiming timing = sumTiming(*setup.runner);
  timing.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  BuildResult result =
      assembleMap(*setup.object, *setup.hand, options, ledger.takePrefix(), false, timing);
  if (result.status == BuildStatus::kNoGrasps) {
    checkpoint.remove();
    std::cerr << "taskmap-mpi build: error: " << result.message << "; nothing written to '"
              << args.output << "'\n";
    return 3;
  }
  if (args.timestamp) result.map.created_utc = mapCreationTime(true);
  const std::optional<HoldLabels> labels = labelHolds(
      holdValidation(args), options.threads, options.clustering, *setup.hand, nullptr, &result.map);
  printHoldLabels("taskmap-mpi build", labels, args.keep_holding, args.quiet);
  const auto t_write = std::chrono::steady_clock::now();
  writeMap(args.output, result.map);
  checkpoint.remove();
  const double write_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_write).count();
  const int threads = buildThreadCount(options.threads);
  printBuildSummary("taskmap-mpi build", args, result, write_seconds,
                    std::to_string(world.size) + " ranks x " + std::to_string(threads) +
                        " (rank 0; not stored: the map does not depend on it); blocks of " +
                        std::to_string(block_trials) + " trials, " + std::to_string(resumed) +
                        " resumed from the checkpoint, " + std::to_string(simulated) +
                        " trials simulated now");
  return 0;
}

}  // namespace taskmap::cli
