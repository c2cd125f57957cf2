// taskmap dataset: one task map per (object, hand), jobs one after another on all threads;
// the same maps and manifest as `taskmap-mpi dataset` on any number of ranks.
#include <chrono>
#include <iostream>
#include <memory>
#include <vector>

#include "command.hpp"
#include "dataset.hpp"
#include "run_lock.hpp"

namespace taskmap::cli {
namespace {

void runDataset(const DatasetArgs& args) {
  const DatasetPlan plan = planDataset(args);
  const RunLock lock(datasetLockPath(plan), "data set directory '" + plan.dir + "'");
  DatasetManifest manifest(plan);
  const bool quiet = args.knobs.quiet;
  if (!manifest.note().empty()) std::cerr << "taskmap dataset: " << manifest.note() << "\n";
  const std::vector<std::size_t> todo = manifest.startRun();  // largest first
  const std::size_t skipped = plan.jobs.size() - todo.size();
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < todo.size(); ++k) {
    const nlohmann::json entry = runDatasetJob(plan, plan.jobs[todo[k]]);
    manifest.set(todo[k], entry);
    manifest.write();
    if (quiet) continue;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cerr << "taskmap dataset: " << datasetProgressLine(k + 1, todo.size(), elapsed, entry)
              << std::endl;
  }
  manifest.write();
  const std::size_t failed = manifest.failed();
  if (!quiet)
    std::cout << "taskmap dataset: " << plan.jobs.size() << " maps in " << plan.dir << " ("
              << skipped << " finished earlier, " << failed << " failed); manifest " << plan.dir
              << "/manifest.json\n";
  if (failed > 0) {
    std::cerr << "taskmap dataset: " << failed << " of " << plan.jobs.size()
              << " jobs failed; their errors are in " << plan.dir << "/manifest.json\n";
    exitCode() = 1;
  }
}

const CommandRegistrar kRegistrar("dataset", [](CLI::App& app) {
  auto args = std::make_shared<DatasetArgs>();
  CLI::App* cmd = app.add_subcommand(
      "dataset",
      "Build one task map per (object, hand) into a directory with manifest.json. Each job's "
      "seed derives from --seed and the contents of mesh and hand, so the maps depend neither "
      "on the list order nor on how many processes build them (taskmap-mpi dataset gives the "
      "same). A re-run skips maps whose file and parameters match the manifest; a bad mesh is "
      "recorded there, not fatal (exit code 1 at the end).");
  addDatasetOptions(*cmd, *args);
  cmd->callback([args]() { runDataset(*args); });
});

}  // namespace
}  // namespace taskmap::cli
