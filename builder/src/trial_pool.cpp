#include "trial_pool.hpp"

#include <condition_variable>
#include <ctime>
#include <thread>

namespace taskmap::detail {

double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void Worker::run() {
  std::uint64_t b = 0;
  while (scheduler.claim(&b)) {
    auto block = std::make_unique<Block>();
    const std::uint64_t first = b * scheduler.blockSize();
    const std::uint64_t last = std::min(first + scheduler.blockSize(), scheduler.maxTrials());
    block->trials.reserve(last - first);
    for (std::uint64_t i = first; i < last; ++i) {
      // An incomplete block is dropped.
      if ((stop != nullptr && stop->load()) || scheduler.aborted()) return;
      block->trials.push_back(runTrial(i));
      block->valid += block->trials.back().force_closure;
    }
    scheduler.finish(b, std::move(block));
  }
}

Trial Worker::runTrial(std::uint64_t index) {
  Trial t;
  const double t0 = threadCpuSeconds();
  const Pose initial = sampler.sample(options.seed, index);
  const double t1 = threadCpuSeconds();
  GraspResult g = simulator.simulate(initial);
  const double t2 = threadCpuSeconds();
  times.sampling += t1 - t0;
  times.simulation += t2 - t1;
  ++times.trials;
  t.status = g.status;
  if (g.status != GraspStatus::kOk) return t;
  const QualityResult q = evaluateGrasp(g.contacts, com, torque_scale, options.quality);
  times.quality += threadCpuSeconds() - t2;
  t.force_closure = q.force_closure;
  t.epsilon = q.epsilon;
  t.volume = q.volume;
  if (t.force_closure || options.keep_invalid)
    t.grasp = std::make_unique<GraspResult>(std::move(g));
  return t;
}

void runTrialPool(const TrialPoolSetup& setup, Scheduler& scheduler, BuildTiming& timing) {
  const BuildOptions& options = setup.options;
  const int threads = setup.threads;
  const std::atomic<bool>* stop = setup.stop;
  const ProgressCallback& progress = setup.progress;
  const auto t_trials = Clock::now();
  std::vector<Worker> workers;
  workers.reserve(static_cast<std::size_t>(threads));
  for (int w = 0; w < threads; ++w)
    workers.push_back(Worker{setup.sampler,
                             setup.simulator,
                             options,
                             setup.center_of_mass,
                             setup.torque_scale,
                             scheduler,
                             stop,
                             {}});
  std::vector<std::thread> pool;
  std::mutex finished_mutex;
  std::condition_variable finished_cv;
  int running = threads;
  for (int w = 0; w < threads; ++w) {
    try {
      pool.emplace_back([&, w] {
        try {
          workers[static_cast<std::size_t>(w)].run();
        } catch (...) {
          scheduler.abort(std::current_exception());
        }
        std::lock_guard<std::mutex> lock(finished_mutex);
        --running;
        finished_cv.notify_all();
      });
    } catch (...) {  // could not start a thread: stop the others, report after joining
      scheduler.abort(std::current_exception());
      std::lock_guard<std::mutex> lock(finished_mutex);
      running -= threads - w;
      break;
    }
  }
  const auto interval = std::chrono::duration<double>(setup.progress_interval_seconds);
  auto report = [&] {
    if (!progress) return;
    BuildProgress p;
    scheduler.progress(&p.trials_done, &p.valid_found);
    p.valid_target = options.valid_target;
    p.max_trials = options.max_trials;
    p.elapsed_seconds = secondsSince(t_trials);
    try {
      progress(p);
    } catch (...) {  // the workers must be joined before the exception leaves
      scheduler.abort(std::current_exception());
    }
  };
  {
    std::unique_lock<std::mutex> lock(finished_mutex);
    while (running > 0) {
      finished_cv.wait_for(lock, interval, [&] { return running == 0; });
      lock.unlock();
      report();
      lock.lock();
    }
  }
  for (auto& t : pool) t.join();
  if (scheduler.error()) std::rethrow_exception(scheduler.error());
  for (const auto& w : workers) {
    timing.sampling_seconds += w.times.sampling;
    timing.simulation_seconds += w.times.simulation;
    timing.quality_seconds += w.times.quality;
    timing.trials_simulated += w.times.trials;
  }
}

}  // namespace taskmap::detail
