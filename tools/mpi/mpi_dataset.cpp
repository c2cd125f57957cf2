// taskmap-mpi dataset: one job per (object, hand) handed out dynamically, largest first.
#include "mpi_dataset.hpp"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>

#include "build_command.hpp"
#include "task_farm.hpp"
#include "taskmap/core/run_lock.hpp"

namespace taskmap::cli {

int runMpiDataset(const MpiWorld& world, const DatasetArgs& args) {
  // Every rank plans (the same list, the same order); rank 0 alone creates the directory first.
  std::optional<DatasetPlan> plan;
  std::optional<RunLock> lock;  // rank 0's, on the directory
  std::string error;
  if (world.rank == 0) {
    try {
      plan = planDataset(datasetOptions(args));
      lock.emplace(datasetLockPath(*plan), "data set directory '" + plan->dir + "'");
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  if (!agreeAllOk(world, error, "taskmap-mpi dataset")) return 1;
  if (world.rank != 0) {
    try {
      plan = planDataset(datasetOptions(args));
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  if (!agreeAllOk(world, error, "taskmap-mpi dataset")) return 1;

  FarmTasks tasks;
  tasks.run = [&plan, &args](std::uint64_t i) {
    const DatasetEntry entry = runDatasetJob(*plan, plan->jobs[i]);
    printHoldLabels("taskmap-mpi dataset", entry.validation, args.knobs.keep_holding,
                    args.knobs.quiet);
    return datasetEntryJson(entry);
  };
  if (world.rank != 0) {
    runFarm(world, tasks);
    return 0;
  }
  DatasetManifest manifest(*plan);
  if (!manifest.note().empty()) std::cerr << "taskmap-mpi dataset: " << manifest.note() << "\n";
  std::vector<std::uint64_t> todo;  // largest first
  for (std::size_t i : manifest.startRun()) todo.push_back(i);
  const std::size_t skipped = plan->jobs.size() - todo.size();
  std::size_t next = 0, done = 0;
  const bool quiet = args.knobs.quiet;
  const auto t0 = std::chrono::steady_clock::now();
  tasks.next = [&](std::uint64_t* i) {
    if (next >= todo.size()) return false;
    *i = todo[next++];
    return true;
  };
  tasks.accept = [&](std::uint64_t i, std::string result) {
    const DatasetEntry entry = datasetEntryFromJson(result);
    manifest.set(i, entry);
    manifest.write();
    ++done;
    if (quiet) return;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cerr << "taskmap-mpi dataset: " << datasetProgressLine(done, todo.size(), elapsed, entry)
              << std::endl;
  };
  runFarm(world, tasks);
  manifest.write();
  const std::size_t failed = manifest.failed();
  if (!quiet)
    std::cout << "taskmap-mpi dataset: " << plan->jobs.size() << " maps in " << plan->dir << " ("
              << skipped << " finished earlier, " << failed << " failed) on " << world.size
              << " ranks; manifest " << plan->dir << "/manifest.json\n";
  if (failed == 0) return 0;
  std::cerr << "taskmap-mpi dataset: " << failed << " of " << plan->jobs.size()
            << " jobs failed; their errors are in " << plan->dir << "/manifest.json\n";
  return 1;
}

}  // namespace taskmap::cli
