#pragma once
// The trial pool of a build (private to builder): worker threads claim fixed blocks of trial
// indices, sample and simulate a block's trials, then score them, and hand the finished block
// to a Scheduler that keeps blocks by index and stops when the completed prefix holds
// valid_target force-closure grasps. Results depend only on (seed, trial index), never on the
// thread count.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "taskmap/builder/map_builder.hpp"
#include "taskmap/builder/trial_block.hpp"

namespace taskmap::detail {

using Clock = std::chrono::steady_clock;

/// CPU time of the calling thread, seconds: stage shares stay meaningful on a loaded machine.
double threadCpuSeconds();

/// Wall seconds since t0.
double secondsSince(Clock::time_point t0);

/// Worker threads for BuildOptions::threads: itself when positive, else the cores this process
/// may run on (its CPU affinity mask, so `mpirun --bind-to core` or taskset are respected).
int threadCount(int requested);

/// Spacing of the finger points the antipodal_palm sampler tests for being inside, metres.
constexpr double kFingerCheckSpacing = 0.01;

/// The sampler a build runs: options.sampler.kind, or the hand's default (defaultSamplerKind:
/// antipodal_palm for parallel jaws, mixed for other hands) when it is unset.
SamplerKind samplerKindFor(const BuildOptions& options, const HandModel& hand);

/// The options the sampler gets: the kind (samplerKindFor), the hand's approach axis, the build's
/// friction, the jaws and finger points the kind needs, and (antipodal_palm) whether the palm must
/// touch.
SamplerOptions samplerOptionsFor(const BuildOptions& options, const HandModel& hand);

/// The closing checker of a build, or null when options.closing_check is off.
std::unique_ptr<const ClosingChecker> makeClosingChecker(const ObjectModel& object,
                                                         const HandModel& hand,
                                                         const BuildOptions& options);

/// Trials per work block: options.block_size, at most kHoldTestBlockSize with the hold test (a
/// tested grasp costs the time of thousands of trials, and a thread's block past the valid
/// target is work thrown away). Results do not depend on it.
std::uint64_t blockSize(const BuildOptions& options);
constexpr std::uint64_t kHoldTestBlockSize = 4;

/// The physics hold tester of a build, or null when options.hold_test is off.
std::unique_ptr<const RobustHoldTester> makeHoldTester(const ObjectModel& object,
                                                       const HandModel& hand,
                                                       const BuildOptions& options);

struct StageTimes {
  double sampling = 0.0, simulation = 0.0, quality = 0.0, closing_check = 0.0, hold_test = 0.0;
  std::uint64_t trials = 0;
  std::uint64_t closing_checks = 0;  ///< grasps the closing check simulated
  std::uint64_t hold_tests = 0;      ///< grasps the hold test simulated
  long long hold_test_steps = 0;     ///< their MuJoCo steps
  std::uint64_t scored = 0;          ///< ok grasps scored
};

// Shared state of one run of the pool over the trials [first, last): blocks of block_size
// trials, done when every block finished or the completed prefix holds valid_target
// force-closure grasps (pass UINT64_MAX to run every block).
class Scheduler {
 public:
  Scheduler(std::uint64_t first, std::uint64_t last, std::uint64_t block_size,
            std::uint64_t valid_target)
      : first_(first),
        last_(last),
        block_size_(block_size),
        valid_target_(valid_target),
        // Without wrap-around for any range (last - first + block_size - 1 could overflow).
        count_((last - first) / block_size + ((last - first) % block_size != 0 ? 1 : 0)) {}

  std::uint64_t blockCount() const { return count_; }
  // Trial range of block b.
  std::uint64_t blockFirst(std::uint64_t b) const { return first_ + b * block_size_; }
  std::uint64_t blockLast(std::uint64_t b) const {
    return blockFirst(b) + std::min(block_size_, last_ - blockFirst(b));  // no wrap-around
  }

  // Next block index to run, or false when there is no more work wanted.
  bool claim(std::uint64_t* block) {
    if (done_.load() || aborted_.load()) return false;
    const std::uint64_t b = next_.fetch_add(1);
    if (b >= count_) return false;
    *block = b;
    return true;
  }

  void finish(std::uint64_t b, std::unique_ptr<TrialBlock> block) {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::uint64_t valid = block->valid();
    trials_done_ += block->trials.size();
    valid_done_ += valid;
    ++blocks_done_;
    // The table grows with the blocks finished, not with the trial budget: a budget of 2^64
    // trials costs nothing until its blocks run.
    if (b >= blocks_.size()) blocks_.resize(b + 1);
    blocks_[b] = std::move(block);
    // The prefix ends at the block that completes the target (it may end at that trial).
    while (prefix_ < blocks_.size() && blocks_[prefix_] && prefix_valid_ < valid_target_) {
      prefix_valid_ += blocks_[prefix_]->valid();
      ++prefix_;
    }
    if (prefix_valid_ >= valid_target_ || prefix_ == count_) done_.store(true);
  }

  // When every block before b has finished (b is the first unfinished one): true, and *valid =
  // the force-closure grasps in them. Else false (the count is not known yet).
  bool validBefore(std::uint64_t b, std::uint64_t* valid) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (prefix_ != b) return false;
    *valid = prefix_valid_;
    return true;
  }
  std::uint64_t validTarget() const { return valid_target_; }

  bool done() const { return done_.load(); }
  // A worker failed: remember the first exception and stop every worker.
  void abort(std::exception_ptr error) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_) error_ = std::move(error);
    aborted_.store(true);
  }
  bool aborted() const { return aborted_.load(); }
  std::exception_ptr error() const { return error_; }
  void progress(BuildProgress* p) {
    std::lock_guard<std::mutex> lock(mutex_);
    p->trials_done = trials_done_;
    p->valid_found = valid_done_;
    p->blocks_done = blocks_done_;
    p->blocks_total = count_;
  }
  // Completed blocks 0..prefix-1 (only call after the workers joined).
  std::uint64_t prefix() const { return prefix_; }
  // Moves the completed prefix out, in index order (only call after the workers joined).
  std::vector<TrialBlock> takePrefixBlocks() {
    std::vector<TrialBlock> out;
    out.reserve(prefix_);
    for (std::uint64_t b = 0; b < prefix_; ++b) out.push_back(std::move(*blocks_[b]));
    return out;
  }

 private:
  const std::uint64_t first_, last_, block_size_, valid_target_, count_;
  std::vector<std::unique_ptr<TrialBlock>> blocks_;
  std::atomic<std::uint64_t> next_{0};
  std::atomic<bool> done_{false};
  std::atomic<bool> aborted_{false};
  std::exception_ptr error_;
  std::mutex mutex_;
  std::uint64_t prefix_ = 0, prefix_valid_ = 0, trials_done_ = 0, valid_done_ = 0, blocks_done_ = 0;
};

struct Worker {
  const Sampler& sampler;
  const GraspSimulator& simulator;
  const ClosingChecker* closing;  ///< null when the closing check is off
  const RobustHoldTester* hold;   ///< null when the hold test is off
  const BuildOptions& options;
  const Eigen::Vector3d com;
  const double torque_scale;
  Scheduler& scheduler;
  const std::atomic<bool>* stop;
  StageTimes times;

  void run();
  /// How many of the `left` trials still to run in block b to simulate before scoring (0: the
  /// valid target is complete).
  std::uint64_t trialsWanted(std::uint64_t b, const TrialBlock& block, std::uint64_t left);
  /// Scores the simulated trials of block b into `block` (none past the valid target).
  void scoreBlock(std::uint64_t b, std::vector<GraspResult>& simulated, TrialBlock& block);
  /// Samples and simulates trial `index`.
  GraspResult simulateTrial(std::uint64_t index);
  /// Scores a simulated trial (the quality of an ok grasp) into its outcome.
  TrialOutcome scoreTrial(GraspResult g);
  /// The hold filter's verdict on a simulated (status ok) grasp.
  bool holds(const GraspResult& g) const;
  /// The physics hold test of a force-closure grasp: its result, and t's verdict (not_holding
  /// when it fails).
  RobustHoldResult holdTest(const GraspResult& g, TrialOutcome& t);
  /// The part of g a map stores, moved out of g.
  static std::unique_ptr<TrialGrasp> takeGrasp(GraspResult& g);
  /// Ends a trial refused before its quality (squeeze-force test, hold filter; t's flag set):
  /// its CPU since t0 counts as quality, and a build that stores every completed trial keeps
  /// its grasp.
  TrialOutcome refused(TrialOutcome t, GraspResult& g, double t0);
};

/// Everything runTrialPool needs.
struct TrialPoolSetup {
  const Sampler& sampler;
  const GraspSimulator& simulator;
  const ClosingChecker* closing;  ///< null when the closing check is off
  const RobustHoldTester* hold;   ///< null when the hold test is off
  const BuildOptions& options;
  Eigen::Vector3d center_of_mass;
  double torque_scale;
  int threads;                       ///< >= 1
  const std::atomic<bool>* stop;     ///< may be null
  const ProgressCallback& progress;  ///< may be empty
  double progress_interval_seconds;  ///< > 0
};

/// Runs the trials on setup.threads threads until the scheduler is done, the stop flag rises or a
/// worker fails (rethrown here after every thread joined). Adds the workers' stage times to
/// timing.
void runTrialPool(const TrialPoolSetup& setup, Scheduler& scheduler, BuildTiming& timing);

}  // namespace taskmap::detail
