// taskmap-mpi: the map build (and data sets of maps) over the ranks of an MPI job. Same
// results as `taskmap build` / `taskmap dataset` for any number of ranks and threads.
#include <mpi.h>

#include <cstdio>
#include <iostream>
#include <sstream>
#include <thread>

#include <CLI/CLI.hpp>

#include "build_command.hpp"
#include "mpi_build.hpp"
#include "mpi_common.hpp"
#include "mpi_dataset.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap::cli {

bool agreeAllOk(const MpiWorld& world, const std::string& error, const std::string& label) {
  const int mine = error.empty() ? world.size : world.rank;
  int first_failed = world.size;
  MPI_Allreduce(&mine, &first_failed, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (first_failed == world.size) return true;
  if (first_failed == world.rank) {
    std::cerr << label << ": error";
    if (world.rank != 0) std::cerr << " (rank " << world.rank << ")";
    std::cerr << ": " << error << std::endl;
  }
  return false;
}

namespace {

// mpirun binds each rank to a core by default (for 2 ranks or fewer), which would leave
// `--threads 0` one thread: say so on rank 0.
void warnAboutBinding(const MpiWorld& world, int threads_option, bool quiet) {
  if (world.rank != 0 || threads_option != 0 || quiet) return;
  const int allowed = buildThreadCount(0);
  const auto cores = static_cast<int>(std::thread::hardware_concurrency());
  if (allowed >= cores) return;
  std::cerr << "taskmap-mpi: rank 0 may run on " << allowed << " of " << cores
            << " cores (its CPU affinity), so --threads 0 starts " << allowed
            << " thread(s) a rank; to give each rank all cores of its node start with "
               "`mpirun --bind-to none` (Slurm: --cpus-per-task)\n";
}

int run(const MpiWorld& world, int argc, char** argv) {
  CLI::App app{"taskmap-mpi " TASKMAP_VERSION
               ": build grasp task maps on the ranks of an MPI job (mpirun, srun)"};
  app.set_version_flag("--version", std::string("taskmap-mpi ") + TASKMAP_VERSION);
  app.require_subcommand(1);
  BuildArgs build_args;
  std::uint64_t block_trials = 256;
  CLI::App* build = app.add_subcommand(
      "build",
      "Build a task map on every rank: rank 0 hands out blocks of trials, each rank runs them "
      "on its threads, rank 0 writes the map. Same options and same map as `taskmap build`, "
      "for any number of ranks and threads. A killed job re-run with the same command resumes "
      "from the checkpoint <output>.ckpt.");
  addBuildOptions(*build, build_args);
  build
      ->add_option("--block-trials", block_trials,
                   "trials per block handed to a rank (does not change the map)")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  DatasetArgs dataset_args;
  CLI::App* dataset = app.add_subcommand(
      "dataset",
      "Build one task map per (object, hand) on the ranks: jobs handed out largest first, each "
      "rank writes its maps, rank 0 keeps DIR/manifest.json. The same maps and manifest as "
      "`taskmap dataset` for any number of ranks; a re-run skips finished maps.");
  addDatasetOptions(*dataset, dataset_args);
  std::ostringstream quiet_out, quiet_err;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Every rank parses the same command line; only rank 0 speaks.
    return world.rank == 0 ? app.exit(e) : app.exit(e, quiet_out, quiet_err);
  }
  if (build->parsed()) {
    warnAboutBinding(world, build_args.threads, build_args.quiet);
    return runMpiBuild(world, build_args, block_trials);
  }
  if (dataset->parsed()) {
    warnAboutBinding(world, dataset_args.knobs.threads, dataset_args.knobs.quiet);
    return runMpiDataset(world, dataset_args);
  }
  return 2;
}

}  // namespace
}  // namespace taskmap::cli

int main(int argc, char** argv) {
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  taskmap::cli::MpiWorld world;
  MPI_Comm_rank(MPI_COMM_WORLD, &world.rank);
  MPI_Comm_size(MPI_COMM_WORLD, &world.size);
  int code = 0;
  try {
    code = taskmap::cli::run(world, argc, argv);
  } catch (const taskmap::Error& e) {
    std::cerr << "taskmap-mpi: error (rank " << world.rank << "): " << e.what() << std::endl;
    MPI_Abort(MPI_COMM_WORLD, 1);
  } catch (const std::exception& e) {
    std::cerr << "taskmap-mpi: internal error (rank " << world.rank << "): " << e.what()
              << std::endl;
    MPI_Abort(MPI_COMM_WORLD, 3);
  }
  MPI_Finalize();
  return code;
}
