#include "trial_pool.hpp"

#include <sched.h>

#include <algorithm>
#include <condition_variable>
#include <ctime>
#include <limits>
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

int threadCount(int requested) {
  if (requested > 0) return requested;
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

SamplerKind samplerKindFor(const BuildOptions& options, const HandModel& hand) {
  return options.sampler.kind ? *options.sampler.kind : defaultSamplerKind(hand);
}

SamplerOptions samplerOptionsFor(const BuildOptions& options, const HandModel& hand) {
  SamplerOptions o = options.sampler;
  o.kind = samplerKindFor(options, hand);
  o.approach_axis = hand.approachAxis().normalized();
  o.friction = options.quality.friction;
  if (!o.jaws) o.jaws = jawGeometry(hand);
  if (o.kind == SamplerKind::kEnclose && o.finger_points.empty())
    o.finger_points = openFingerPoints(hand);
  if (o.kind == SamplerKind::kPalmEnclose) {
    if (!o.enclose) o.enclose = encloseGeometry(hand);
    if (o.finger_points.empty())
      o.finger_points = coarseToFine(fingerCheckPoints(hand, kFingerCheckSpacing));
  }
  if (o.kind == SamplerKind::kAntipodalPalm) {
    if (o.finger_points.empty()) o.finger_points = fingerCheckPoints(hand, kFingerCheckSpacing);
    const GraspMode mode = options.simulation.grasp_mode.value_or(hand.graspMode());
    o.place_palm = mode == GraspMode::kPalm && options.simulation.require_palm_contact;
  }
  return o;
}

std::unique_ptr<const ClosingChecker> makeClosingChecker(const ObjectModel& object,
                                                         const HandModel& hand,
                                                         const BuildOptions& options) {
  if (options.closing_check.mode == ClosingCheckMode::kOff) return nullptr;
  return std::make_unique<const ClosingChecker>(object, hand, options.closing_check);
}

std::uint64_t blockSize(const BuildOptions& options) {
  if (options.hold_test == BuildHoldTest::kOff) return options.block_size;
  return std::min(options.block_size, kHoldTestBlockSize);
}

std::unique_ptr<const RobustHoldTester> makeHoldTester(const ObjectModel& object,
                                                       const HandModel& hand,
                                                       const BuildOptions& options) {
  if (options.hold_test == BuildHoldTest::kOff) return nullptr;
  RobustHoldOptions o = options.hold_test_options;
  o.all_variants = false;
  o.protocol_label = false;
  if (options.hold_test == BuildHoldTest::kNominal) {  // the protocol alone, no margin
    o.palm_shift = o.palm_turn = o.friction = 0.0;
    o.decomposition_faces = 0;
    o.margin_translation = o.margin_rotation = std::numeric_limits<double>::infinity();
  }
  return std::make_unique<const RobustHoldTester>(hand, object, o);
}

// A block is simulated, then scored: each stage then runs on caches its previous trial left
// warm (the quality of a many-contact grasp touches megabytes, which would evict the object's
// tree between two simulations). Outcomes do not depend on the order. Once every earlier block
// has finished, a block is simulated in parts of at most the force-closure grasps still missing
// (trialsWanted) and ends at the trial that completes valid_target: the build stores nothing
// past it (takePrefix stops there), so the trials after it are not simulated.
void Worker::run() {
  std::uint64_t b = 0;
  std::vector<GraspResult> simulated;
  while (scheduler.claim(&b)) {
    auto block = std::make_unique<TrialBlock>();
    const std::uint64_t first = scheduler.blockFirst(b);
    const std::uint64_t last = scheduler.blockLast(b);
    block->first = first;
    block->trials.reserve(std::min<std::uint64_t>(last - first, 4096));  // grows past that
    for (std::uint64_t i = first; i < last;) {
      const std::uint64_t end = i + trialsWanted(b, *block, last - i);
      if (end == i) break;  // the target is complete
      simulated.clear();
      for (; i < end; ++i) {
        // An incomplete block is dropped.
        if ((stop != nullptr && stop->load()) || scheduler.aborted()) return;
        simulated.push_back(simulateTrial(i));
      }
      scoreBlock(b, simulated, *block);
    }
    scheduler.finish(b, std::move(block));
  }
}

// How many of the `left` trials still to run in block b to simulate before scoring: all of them
// while an earlier block is unfinished; then at most the force-closure grasps still missing
// (a trial adds at most one), none once valid_target is complete.
std::uint64_t Worker::trialsWanted(std::uint64_t b, const TrialBlock& block, std::uint64_t left) {
  std::uint64_t valid = 0;
  if (!scheduler.validBefore(b, &valid)) return left;
  valid += block.valid();
  const std::uint64_t target = scheduler.validTarget();
  return valid >= target ? 0 : std::min(left, target - valid);
}

// Scores the simulated trials, appending them to the block in order. When every earlier block
// has finished, the trials past the one that completes valid_target force-closure grasps are
// not scored: the build stores none of them (takePrefix stops at that trial), so they keep
// their simulation status only.
void Worker::scoreBlock(std::uint64_t b, std::vector<GraspResult>& simulated, TrialBlock& block) {
  std::uint64_t valid = 0;
  const bool known = scheduler.validBefore(b, &valid);
  valid += block.valid();
  for (GraspResult& g : simulated) {
    if (known && valid >= scheduler.validTarget()) {
      TrialOutcome t;
      t.status = g.status;
      block.trials.push_back(std::move(t));
      continue;
    }
    block.trials.push_back(scoreTrial(std::move(g)));
    valid += block.trials.back().force_closure ? 1 : 0;
  }
}

GraspResult Worker::simulateTrial(std::uint64_t index) {
  const double t0 = threadCpuSeconds();
  const Pose initial = sampler.sample(options.seed, index);
  const double t1 = threadCpuSeconds();
  GraspResult g = simulator.simulate(initial, FailureDetail::kStatus);  // a failure: its status
  times.sampling += t1 - t0;
  times.simulation += threadCpuSeconds() - t1;
  ++times.trials;
  return g;
}

TrialOutcome Worker::scoreTrial(GraspResult g) {
  TrialOutcome t;
  t.status = g.status;
  if (g.status != GraspStatus::kOk) return t;
  ++times.scored;
  const double t0 = threadCpuSeconds();
  if (options.min_squeeze_force > 0.0 &&
      graspSqueezeForce(simulator.hand(), g.pose, g.joints, g.contacts) <
          options.min_squeeze_force) {
    t.weak_squeeze = true;
    return refused(std::move(t), g, t0);
  }
  if (options.hold_filter.enabled && !holds(g)) {
    t.unbalanced = true;
    return refused(std::move(t), g, t0);
  }
  const QualityResult q = evaluateGrasp(g.contacts, com, torque_scale, options.quality);
  t.force_closure = q.force_closure;
  t.epsilon = q.epsilon;
  t.volume = q.volume;
  if (t.force_closure && closing != nullptr) {  // only grasps a map could store
    const double t1 = threadCpuSeconds();
    t.pushed = !closing->check(g.pose, g.joints).holds;
    t.force_closure = !t.pushed;
    times.closing_check += threadCpuSeconds() - t1;
    ++times.closing_checks;
  }
  times.quality += threadCpuSeconds() - t0;
  std::optional<RobustHoldResult> tested;
  if (t.force_closure && hold != nullptr) tested = holdTest(g, t);
  if (t.force_closure || options.stored == StoredGrasps::kAllCompleted) {
    t.grasp = takeGrasp(g);
    t.grasp->hold = std::move(tested);
  }
  return t;
}

RobustHoldResult Worker::holdTest(const GraspResult& g, TrialOutcome& t) {
  const double t0 = threadCpuSeconds();
  RobustHoldResult r = hold->test(g.pose, g.joints);
  times.hold_test += threadCpuSeconds() - t0;
  ++times.hold_tests;
  times.hold_test_steps += r.steps;
  // kNominal's tester has one variant, the protocol without a margin: robust means it holds.
  t.not_holding = !r.robust;
  t.force_closure = r.robust;
  return r;
}

std::unique_ptr<TrialGrasp> Worker::takeGrasp(GraspResult& g) {
  return std::make_unique<TrialGrasp>(
      TrialGrasp{g.pose, std::move(g.joints), std::move(g.contacts), std::nullopt});
}

TrialOutcome Worker::refused(TrialOutcome t, GraspResult& g, double t0) {
  times.quality += threadCpuSeconds() - t0;
  if (options.stored == StoredGrasps::kAllCompleted) t.grasp = takeGrasp(g);
  return t;
}

bool Worker::holds(const GraspResult& g) const {
  const SqueezeDrive drive =
      squeezeDrive(simulator.hand(), g.pose, g.joints, g.contacts, options.hold_filter);
  return squeezeBalance(g.contacts, drive, com, torque_scale, options.hold_filter.balance).balanced;
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
                             setup.closing,
                             setup.hold,
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
    scheduler.progress(&p);
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
    // At least one report, the last one after every worker finished: a build that ends before
    // the first interval still reports its final state (and a throwing callback still throws).
    std::unique_lock<std::mutex> lock(finished_mutex);
    do {
      finished_cv.wait_for(lock, interval, [&] { return running == 0; });
      lock.unlock();
      report();
      lock.lock();
    } while (running > 0);
  }
  for (auto& t : pool) t.join();
  if (scheduler.error()) std::rethrow_exception(scheduler.error());
  for (const auto& w : workers) {
    timing.sampling_seconds += w.times.sampling;
    timing.simulation_seconds += w.times.simulation;
    timing.quality_seconds += w.times.quality;
    timing.closing_check_seconds += w.times.closing_check;
    timing.closing_checks += w.times.closing_checks;
    timing.hold_test_seconds += w.times.hold_test;
    timing.hold_tests += w.times.hold_tests;
    timing.hold_test_steps += w.times.hold_test_steps;
    timing.trials_simulated += w.times.trials;
    timing.grasps_scored += w.times.scored;
  }
}

}  // namespace taskmap::detail
