// taskmap dataset: one task map per (object, hand), jobs one after another on all threads;
// the same maps and manifest as `taskmap-mpi dataset` on any number of ranks.
#include <iostream>
#include <memory>

#include "build_command.hpp"
#include "command.hpp"
#include "taskmap/core/stop_signals.hpp"

namespace taskmap::cli {
namespace {

void runDataset(const DatasetArgs& args) {
  // Plan, the directory's lock (a second run refuses with the holder's PID), the manifest.
  DatasetRun run(datasetOptions(args));
  const bool quiet = args.knobs.quiet;
  if (!run.note().empty()) std::cerr << "taskmap dataset: " << run.note() << "\n";
  RunControl<DatasetProgress> control;
  control.progress = [&args, quiet](const DatasetProgress& p) {
    printHoldLabels("taskmap dataset", p.entry.validation, args.knobs.keep_holding, quiet);
    if (quiet) return;
    std::cerr << "taskmap dataset: "
              << datasetProgressLine(p.done, p.total, p.elapsed_seconds, p.entry) << std::endl;
  };
  control.stop = StopSignals::flag();
  DatasetResult result;
  {
    const StopSignals signals;  // Ctrl-C: the current job stops unwritten, later ones stay pending
    result = run.run(control);
  }
  if (result.interrupted) {
    std::cerr << "taskmap dataset: interrupted; the maps written so far and manifest.json stay, "
                 "a re-run builds the pending jobs\n";
    exitCode() = 130;
    return;
  }
  if (!quiet)
    std::cout << "taskmap dataset: " << result.jobs << " maps in " << result.dir << " ("
              << result.skipped << " finished earlier, " << result.failed << " failed); manifest "
              << result.dir << "/manifest.json\n";
  if (result.failed > 0) {
    std::cerr << "taskmap dataset: " << result.failed << " of " << result.jobs
              << " jobs failed; their errors are in " << result.dir << "/manifest.json\n";
    exitCode() = 1;
  }
}

const CommandRegistrar kRegistrar(
    "dataset", "Build one map per (object, hand) into a directory with a manifest",
    [](CLI::App& app) {
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
