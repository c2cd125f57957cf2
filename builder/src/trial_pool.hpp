#pragma once
// The trial pool of a build (private to builder): worker threads claim fixed blocks of trial
// indices, run each trial (sample, simulate, score) and hand the finished block to a Scheduler
// that keeps blocks by index and stops when the completed prefix holds valid_target
// force-closure grasps. Results depend only on (seed, trial index), never on the thread count.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include <Eigen/Core>

#include "taskmap/builder/map_builder.hpp"

namespace taskmap::detail {

using Clock = std::chrono::steady_clock;

/// CPU time of the calling thread, seconds: stage shares stay meaningful on a loaded machine.
double threadCpuSeconds();

/// Wall seconds since t0.
double secondsSince(Clock::time_point t0);

// One trial's outcome; the grasp itself only when it may be stored.
struct Trial {
  GraspStatus status = GraspStatus::kNoFingerContact;
  bool force_closure = false;
  std::unique_ptr<GraspResult> grasp;  // status ok and (force closure or keep_invalid)
  double epsilon = 0.0;
  double volume = 0.0;
};

struct Block {
  std::vector<Trial> trials;
  std::uint64_t valid = 0;
};

struct StageTimes {
  double sampling = 0.0, simulation = 0.0, quality = 0.0;
  std::uint64_t trials = 0;
};

// Shared state of one build.
class Scheduler {
 public:
  Scheduler(std::uint64_t max_trials, std::uint64_t block_size, std::uint64_t valid_target)
      : max_trials_(max_trials),
        block_size_(block_size),
        valid_target_(valid_target),
        blocks_((max_trials + block_size - 1) / block_size) {}

  std::uint64_t blockCount() const { return blocks_.size(); }
  std::uint64_t blockSize() const { return block_size_; }
  std::uint64_t maxTrials() const { return max_trials_; }

  // Next block index to run, or false when there is no more work wanted.
  bool claim(std::uint64_t* block) {
    if (done_.load() || aborted_.load()) return false;
    const std::uint64_t b = next_.fetch_add(1);
    if (b >= blocks_.size()) return false;
    *block = b;
    return true;
  }

  void finish(std::uint64_t b, std::unique_ptr<Block> block) {
    std::lock_guard<std::mutex> lock(mutex_);
    trials_done_ += block->trials.size();
    valid_done_ += block->valid;
    blocks_[b] = std::move(block);
    while (prefix_ < blocks_.size() && blocks_[prefix_]) {
      prefix_valid_ += blocks_[prefix_]->valid;
      ++prefix_;
    }
    if (prefix_valid_ >= valid_target_ || prefix_ == blocks_.size()) done_.store(true);
  }

  bool done() const { return done_.load(); }
  // A worker failed: remember the first exception and stop every worker.
  void abort(std::exception_ptr error) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!error_) error_ = std::move(error);
    aborted_.store(true);
  }
  bool aborted() const { return aborted_.load(); }
  std::exception_ptr error() const { return error_; }
  void progress(std::uint64_t* trials, std::uint64_t* valid) {
    std::lock_guard<std::mutex> lock(mutex_);
    *trials = trials_done_;
    *valid = valid_done_;
  }
  // Completed blocks 0..prefix-1 (only call after the workers joined).
  std::uint64_t prefix() const { return prefix_; }
  Block& block(std::uint64_t b) { return *blocks_[b]; }

 private:
  const std::uint64_t max_trials_, block_size_, valid_target_;
  std::vector<std::unique_ptr<Block>> blocks_;
  std::atomic<std::uint64_t> next_{0};
  std::atomic<bool> done_{false};
  std::atomic<bool> aborted_{false};
  std::exception_ptr error_;
  std::mutex mutex_;
  std::uint64_t prefix_ = 0, prefix_valid_ = 0, trials_done_ = 0, valid_done_ = 0;
};

struct Worker {
  const Sampler& sampler;
  const GraspSimulator& simulator;
  const BuildOptions& options;
  const Eigen::Vector3d com;
  const double torque_scale;
  Scheduler& scheduler;
  const std::atomic<bool>* stop;
  StageTimes times;

  void run();
  Trial runTrial(std::uint64_t index);
};

/// Everything runTrialPool needs.
struct TrialPoolSetup {
  const Sampler& sampler;
  const GraspSimulator& simulator;
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
