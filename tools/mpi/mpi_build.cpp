// taskmap-mpi build: rank 0 hands out fixed blocks of trials on request and runs blocks itself
// on a second thread; every other rank runs the blocks it gets on the threaded trial pool and
// sends back the outcomes. Rank 0 applies buildMap's stop rule, keeps a checkpoint of finished
// blocks beside the output, assembles and writes the map (the same bytes as `taskmap build`).
#include "mpi_build.hpp"

#include <mpi.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <future>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>

#include "block_ledger.hpp"
#include "build_command.hpp"
#include "mpi_common.hpp"
#include "taskmap/builder/build_checkpoint.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap::cli {
namespace {

constexpr int kTagResult = 11;  // worker -> 0: an encoded block (empty: first request)
constexpr int kTagWork = 12;    // 0 -> worker: u64 {first, last}; first == last: stop

// Test hook: TASKMAP_MPI_FAULT="<rank>:<n>" makes that rank kill itself (SIGKILL) when it is
// handed its (n+1)-th block, as a crashed node would.
bool faultNow(int rank, std::uint64_t blocks_sent) {
  const char* fault = std::getenv("TASKMAP_MPI_FAULT");
  if (fault == nullptr) return false;
  int r = -1;
  unsigned long long n = 0;
  return std::sscanf(fault, "%d:%llu", &r, &n) == 2 && r == rank && blocks_sent == n;
}

// Everything of a build every rank has.
struct RankSetup {
  BuildPlan plan;
  std::unique_ptr<ObjectModel> object;
  std::unique_ptr<HandModel> hand;
  std::unique_ptr<TrialRunner> runner;
};

void workerLoop(const MpiWorld& world, TrialRunner& runner) {
  std::string out;  // the finished block; empty on the first request
  std::uint64_t sent = 0;
  for (;;) {
    MPI_Send(out.data(), static_cast<int>(out.size()), MPI_BYTE, 0, kTagResult, MPI_COMM_WORLD);
    std::uint64_t work[2] = {0, 0};
    MPI_Recv(work, 2, MPI_UINT64_T, 0, kTagWork, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (work[0] == work[1]) return;
    if (faultNow(world.rank, sent)) std::raise(SIGKILL);
    TrialBlock block;
    runner.run(work[0], work[1], &block);
    out = encodeTrialBlock(block);
    ++sent;
  }
}

// Rank 0: hands out blocks, runs blocks on a local thread, records results.
class Coordinator {
 public:
  Coordinator(const MpiWorld& world, const RankSetup& setup, BlockLedger& ledger,
              BuildCheckpoint& checkpoint, ProgressPrinter& printer)
      : world_(world), setup_(setup), ledger_(ledger), checkpoint_(checkpoint), printer_(printer) {}

  void run() {
    const auto t0 = std::chrono::steady_clock::now();
    auto last_report = t0;
    int active = world_.size - 1;  // workers not yet told to stop
    for (;;) {
      bool busy = pollLocal();
      busy = serveWorker(&active) || busy;
      if (!local_ && active == 0) break;
      const auto now = std::chrono::steady_clock::now();
      if (now - last_report > std::chrono::milliseconds(250)) {
        report(std::chrono::duration<double>(now - t0).count());
        last_report = now;
      }
      if (!busy) std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    report(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }

  std::uint64_t simulated() const { return simulated_; }

 private:
  void record(TrialBlock block) {
    simulated_ += block.trials.size();
    checkpoint_.append(block);
    if (!ledger_.record(std::move(block)))
      throw Error("internal: a rank returned a block that is not one of this build's");
  }

  // Starts a local block when idle, collects it when finished. True when something happened.
  bool pollLocal() {
    bool happened = false;
    if (local_) {
      if (local_->wait_for(std::chrono::seconds(0)) != std::future_status::ready) return false;
      local_->get();  // rethrows a worker's exception
      local_.reset();
      record(std::move(local_block_));
      happened = true;
    }
    std::uint64_t b = 0;
    if (!ledger_.next(&b)) return happened;
    const std::uint64_t first = ledger_.blockFirst(b), last = ledger_.blockLast(b);
    local_ = std::async(std::launch::async,
                        [this, first, last] { setup_.runner->run(first, last, &local_block_); });
    return true;
  }

  // Answers one waiting worker: records its block, sends the next one or stop.
  bool serveWorker(int* active) {
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, kTagResult, MPI_COMM_WORLD, &flag, &status);
    if (flag == 0) return false;
    int count = 0;
    MPI_Get_count(&status, MPI_BYTE, &count);
    std::string bytes(static_cast<std::size_t>(count), '\0');
    MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, kTagResult, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    if (count > 0) {
      const std::string what = "block from rank " + std::to_string(status.MPI_SOURCE);
      record(decodeTrialBlock(bytes, setup_.hand->jointNames().size(), what));
    }
    std::uint64_t work[2] = {0, 0};
    std::uint64_t b = 0;
    if (ledger_.next(&b)) {
      work[0] = ledger_.blockFirst(b);
      work[1] = ledger_.blockLast(b);
    } else {
      --*active;
    }
    MPI_Send(work, 2, MPI_UINT64_T, status.MPI_SOURCE, kTagWork, MPI_COMM_WORLD);
    return true;
  }

  void report(double elapsed) {
    BuildProgress p;
    p.trials_done = ledger_.trialsDone();
    p.valid_found = ledger_.validFound();
    p.valid_target = setup_.plan.options.valid_target;
    p.max_trials = setup_.plan.options.max_trials;
    p.elapsed_seconds = elapsed;
    p.blocks_done = ledger_.blocksDone();
    p.blocks_total = ledger_.blockCount();
    printer_(p);
  }

  const MpiWorld& world_;
  const RankSetup& setup_;
  BlockLedger& ledger_;
  BuildCheckpoint& checkpoint_;
  ProgressPrinter& printer_;
  std::optional<std::future<void>> local_;
  TrialBlock local_block_;
  std::uint64_t simulated_ = 0;
};

// Loads the inputs on this rank; every rank learns whether all succeeded.
bool setUp(const MpiWorld& world, const BuildArgs& args, RankSetup& setup) {
  std::string error;
  try {
    setup.plan = planBuild(args);
    setup.object =
        std::make_unique<ObjectModel>(ObjectModel::load(args.object, MeshLoadOptions{args.scale}));
    setup.hand = std::make_unique<HandModel>(HandModel::load(setup.plan.hand_urdf));
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
    workerLoop(world, *setup.runner);
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
  std::uint64_t resumed = 0;
  for (TrialBlock& b : checkpoint.takeLoaded()) resumed += ledger.record(std::move(b)) ? 1 : 0;
  ProgressPrinter printer("taskmap-mpi build", ::isatty(STDERR_FILENO) != 0 || args.progress,
                          args.quiet);
  Coordinator coordinator(world, setup, ledger, checkpoint, printer);
  coordinator.run();
  printer.finish();
  BuildTiming timing = sumTiming(*setup.runner);
  timing.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_start).count();
  BuildResult result =
      assembleMap(*setup.object, *setup.hand, options, ledger.takePrefix(), false, timing);
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
                        " resumed from the checkpoint, " + std::to_string(coordinator.simulated()) +
                        " trials simulated now");
  return 0;
}

}  // namespace taskmap::cli
