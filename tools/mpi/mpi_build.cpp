// taskmap-mpi build: rank 0 hands out fixed blocks of trials on request (task_farm.hpp) and runs
// blocks itself on a second thread; every other rank runs the blocks it gets on the threaded
// trial pool and sends back the outcomes. What the ranks compute and rank 0 keeps is builder's
// (distributed_build.hpp: BuildRank, DistributedBuild); this file moves the bytes.
#include "mpi_build.hpp"

#include <mpi.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <memory>

#include "build_command.hpp"
#include "mpi_common.hpp"
#include "task_farm.hpp"
#include "taskmap/builder/distributed_build.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap::cli {
namespace {

// The farm's tasks: every rank runs blocks; rank 0 also hands them out and keeps the results.
FarmTasks buildTasks(const BuildRank& rank, DistributedBuild* book, ProgressPrinter* printer,
                     std::uint64_t block_trials) {
  FarmTasks tasks;
  tasks.run = [&rank, block_trials](std::uint64_t b) { return rank.runBlock(b, block_trials); };
  if (book == nullptr) return tasks;  // a worker rank only runs
  tasks.next = [book](std::uint64_t* b) { return book->next(b); };
  tasks.accept = [book](std::uint64_t b, std::string bytes) { book->accept(b, bytes); };
  const auto t0 = std::chrono::steady_clock::now();
  tasks.tick = [book, printer, t0] {
    (*printer)(book->progress(
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()));
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
std::unique_ptr<BuildRank> setUp(const MpiWorld& world, const BuildArgs& args) {
  std::string error;
  std::unique_ptr<BuildRank> rank;
  try {
    rank = std::make_unique<BuildRank>(fileBuildOptions(args), world.rank == 0);
    if (world.rank == 0) printHandWarnings("taskmap-mpi build", rank->hand());
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (!agreeAllOk(world, error, "taskmap-mpi build")) return nullptr;
  return rank;
}

// Stage CPU seconds and trials summed over the ranks (on rank 0).
BuildTiming sumTiming(const BuildRank& rank) {
  const BuildTiming& t = rank.timing();
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
  const std::unique_ptr<BuildRank> rank = setUp(world, args);
  if (!rank) return 1;
  if (world.rank != 0) {
    runFarm(world, buildTasks(*rank, nullptr, nullptr, block_trials));
    sumTiming(*rank);
    return 0;
  }
  DistributedBuild book(*rank, block_trials);
  const std::string label = "taskmap-mpi build";
  if (!book.checkpointNote().empty() && !args.quiet)
    std::cerr << label << ": " << book.checkpointNote() << "\n";
  announceCheckpointOnStop(args.output + ".ckpt");
  ProgressPrinter printer(label, ::isatty(STDERR_FILENO) != 0 || args.progress, args.quiet);
  runFarm(world, buildTasks(*rank, &book, &printer, block_trials));
  printer.finish();
  BuildTiming timing = sumTiming(*rank);
  timing.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  const FileBuildResult result = book.finish(timing);
  if (result.build.status == BuildStatus::kNoGrasps) {
    std::cerr << label << ": error: " << result.build.message << "; nothing written to '"
              << args.output << "'\n";
    return 3;
  }
  printHoldLabels(label, result.validation, args.keep_holding, args.quiet);
  printBuildSummary(label, args, result.build, result.write_seconds,
                    std::to_string(world.size) + " ranks x " + std::to_string(result.threads) +
                        " (rank 0; not stored: the map does not depend on it); blocks of " +
                        std::to_string(block_trials) + " trials, " +
                        std::to_string(book.resumedBlocks()) + " resumed from the checkpoint, " +
                        std::to_string(book.trialsSimulated()) + " trials simulated now");
  return 0;
}

}  // namespace taskmap::cli
