// The map-building pipeline: deterministic parallel trials in fixed blocks.
#include "taskmap/builder/map_builder.hpp"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <condition_variable>
#include <ctime>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "build_diagnosis.hpp"
#include "taskmap/core/error.hpp"

#ifndef TASKMAP_VERSION
#define TASKMAP_VERSION "unknown"
#endif

namespace taskmap {
namespace {

using Clock = std::chrono::steady_clock;

// CPU time of the calling thread: stage shares stay meaningful on a loaded machine.
double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Outcome names: the simulator's statuses, with ok split by force closure.
constexpr const char* kForceClosure = "force_closure";
constexpr const char* kNotForceClosure = "not_force_closure";

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

  void run() {
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

  Trial runTrial(std::uint64_t index) {
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
};

std::string outcomeName(const Trial& t) {
  if (t.status != GraspStatus::kOk) return toString(t.status);
  return t.force_closure ? kForceClosure : kNotForceClosure;
}

void fillObject(const ObjectModel& object, MapObject& o) {
  const MassProperties& mp = object.massProperties();
  o.name = object.name();
  o.source_sha256 = object.sourceSha256();
  o.scale = object.scale();
  o.volume = mp.volume;
  o.center_of_mass = mp.center_of_mass;
  o.torque_scale = mp.torque_scale;
  const TriangleMesh& mesh = object.mesh();
  o.vertices.resize(static_cast<Eigen::Index>(mesh.vertices.size()), 3);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    o.vertices.row(static_cast<Eigen::Index>(i)) = mesh.vertices[i].transpose();
  o.faces.resize(static_cast<Eigen::Index>(mesh.faces.size()), 3);
  for (std::size_t i = 0; i < mesh.faces.size(); ++i)
    o.faces.row(static_cast<Eigen::Index>(i)) = mesh.faces[i].cast<std::int64_t>().transpose();
}

std::string paramsJson(const BuildOptions& o, int threads, const HandModel& hand) {
  nlohmann::json j = nlohmann::json::object();
  try {
    const auto extra = nlohmann::json::parse(o.extra_params_json);
    if (extra.is_object()) j = extra;
  } catch (const nlohmann::json::exception&) {
    // validate() already refused malformed extra JSON.
  }
  j["sampler"] = toString(o.sampler.kind);
  j["standoff_min"] = o.sampler.standoff_min;
  j["standoff_max"] = o.sampler.standoff_max;
  const Eigen::Vector3d a = hand.approachAxis();
  j["approach_axis"] = {a.x(), a.y(), a.z()};
  j["seed"] = o.seed;
  j["valid"] = o.valid_target;
  j["max_trials"] = o.max_trials;
  j["threads"] = threads;
  j["block_size"] = o.block_size;
  j["keep_invalid"] = o.keep_invalid;
  j["cluster"] = o.cluster;
  j["friction"] = o.quality.friction;
  j["cone_edges"] = o.quality.cone_edges;
  j["contact_model"] = toString(o.quality.contact_model);
  j["torsional_friction"] = o.quality.torsional_friction;
  j["wrench_norm"] = o.quality.norm == WrenchNorm::kL1 ? "l1" : "linf";
  j["contact_tolerance"] = o.simulation.contact_tolerance;
  j["max_retraction"] = o.simulation.max_retraction;
  j["squeeze"] = o.simulation.squeeze;
  j["require_palm_contact"] = o.simulation.require_palm_contact;
  j["check_self_collision"] = o.simulation.check_self_collision;
  j["max_closing_steps"] = o.simulation.max_closing_steps;
  j["cluster_method"] = toString(o.clustering.method);  // requested; /clustering has the one used
  j["cluster_fallback_to_single"] = o.clustering.fallback_to_single;
  j["cluster_outlier_budget"] = o.clustering.outlier_budget;
  j["cluster_min_size_fraction"] = o.clustering.min_size_fraction;
  j["cluster_min_size"] = o.clustering.min_size;
  if (o.clustering.threshold) j["cluster_threshold"] = *o.clustering.threshold;
  if (o.clustering.num_clusters) j["cluster_count"] = *o.clustering.num_clusters;
  return j.dump();
}

// Appends a stored grasp as the next row.
void appendGrasp(const Trial& t, std::size_t row, MapGrasps& g) {
  const GraspResult& r = *t.grasp;
  const auto i = static_cast<Eigen::Index>(row);
  g.pose.row(i) = r.pose.toVector7().transpose();
  assert(r.joints.size() == g.joints.cols());
  g.joints.row(i) = r.joints.transpose();
  g.force_closure.push_back(t.force_closure ? 1 : 0);
  g.epsilon.push_back(t.epsilon);
  g.volume.push_back(t.volume);
  g.contact_offsets.push_back(g.contact_offsets.back() +
                              static_cast<std::int64_t>(r.contacts.size()));
}

}  // namespace

void BuildOptions::validate() const {
  sampler.validate();
  simulation.validate();
  quality.validate();
  if (valid_target < 1) throw Error("valid must be at least 1");
  if (max_trials < 1) throw Error("trials must be at least 1");
  if (threads < 0) throw Error("threads must be 0 (all cores) or positive");
  if (threads > 1024) throw Error("threads must be at most 1024");
  if (block_size < 1) throw Error("block_size must be at least 1");
  try {
    if (!nlohmann::json::parse(extra_params_json).is_object())
      throw Error("extra_params_json must be a JSON object");
  } catch (const nlohmann::json::exception& e) {
    throw Error(std::string("extra_params_json is not valid JSON: ") + e.what());
  }
  if (cluster) {
    ClusteringOptions c = clustering;
    c.rotation_scale = kDefaultRotationScale;  // replaced by the hand's
    c.validate();
  }
}

const char* toString(BuildStatus status) {
  switch (status) {
    case BuildStatus::kComplete:
      return "complete";
    case BuildStatus::kTrialBudgetExhausted:
      return "trial_budget_exhausted";
    case BuildStatus::kInterrupted:
      return "interrupted";
    case BuildStatus::kNoGrasps:
      return "no_grasps";
  }
  return "complete";
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

BuildResult buildMap(const ObjectModel& object, const HandModel& hand, const BuildOptions& options,
                     const ProgressCallback& progress, const std::atomic<bool>* stop,
                     double progress_interval_seconds) {
  options.validate();
  if (!(progress_interval_seconds > 0.0)) throw Error("progress interval must be positive");
  detail::checkObjectSize(object, hand);
  const auto t_start = Clock::now();
  BuildResult result;
  int threads = options.threads;
  if (threads == 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));

  SamplerOptions sampler_options = options.sampler;
  sampler_options.approach_axis = hand.approachAxis().normalized();
  const Sampler sampler(object, sampler_options);
  const GraspSimulator simulator(object, hand, options.simulation);
  const MassProperties& mp = object.massProperties();
  result.timing.setup_seconds = secondsSince(t_start);

  // ---- trials
  const auto t_trials = Clock::now();
  Scheduler scheduler(options.max_trials, options.block_size, options.valid_target);
  std::vector<Worker> workers;
  workers.reserve(static_cast<std::size_t>(threads));
  for (int w = 0; w < threads; ++w)
    workers.push_back(Worker{
        sampler, simulator, options, mp.center_of_mass, mp.torque_scale, scheduler, stop, {}});
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
  const auto interval = std::chrono::duration<double>(progress_interval_seconds);
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
    result.timing.sampling_seconds += w.times.sampling;
    result.timing.simulation_seconds += w.times.simulation;
    result.timing.quality_seconds += w.times.quality;
    result.timing.trials_simulated += w.times.trials;
  }
  const bool interrupted = stop != nullptr && stop->load() && !scheduler.done();

  // ---- assemble: first valid_target force-closure grasps of the completed prefix
  TaskMapData& map = result.map;
  map.generator = std::string("taskmap ") + TASKMAP_VERSION;
  map.created_utc = utcNow();
  fillObject(object, map.object);
  map.hand.name = hand.name();
  map.hand.urdf_sha256 = hand.urdfSha256();
  map.hand.joint_names = hand.jointNames();
  for (const HandLink& l : hand.links()) map.hand.link_names.push_back(l.name);
  map.sampling.sampler = toString(options.sampler.kind);
  map.sampling.seed = options.seed;
  map.sampling.params_json = paramsJson(options, threads, hand);
  map.quality.friction = options.quality.friction;
  map.quality.cone_edges = options.quality.cone_edges;
  map.quality.contact_model = toString(options.quality.contact_model);

  std::uint64_t trials = 0, valid = 0;
  std::vector<const Trial*> stored;
  std::size_t contacts = 0;
  for (std::uint64_t b = 0; b < scheduler.prefix() && valid < options.valid_target; ++b) {
    for (const Trial& t : scheduler.block(b).trials) {
      ++trials;
      ++map.sampling.outcomes[outcomeName(t)];
      if (t.grasp) {
        stored.push_back(&t);
        contacts += t.grasp->contacts.size();
      }
      if (t.force_closure && ++valid == options.valid_target) break;
    }
  }
  map.sampling.trials = trials;

  MapGrasps& g = map.grasps;
  const auto n = static_cast<Eigen::Index>(stored.size());
  const auto joints = static_cast<Eigen::Index>(map.hand.joint_names.size());
  const double rho = hand.rotationScale() > 0.0 ? hand.rotationScale() : kDefaultRotationScale;
  g.rotation_scale = rho;
  g.contacts_available = true;
  g.pose.resize(n, 7);
  g.joints.resize(n, joints);
  g.contact_offsets.assign(1, 0);
  g.contact_points.resize(static_cast<Eigen::Index>(contacts), 3);
  g.contact_normals.resize(static_cast<Eigen::Index>(contacts), 3);
  std::size_t c = 0;
  for (std::size_t i = 0; i < stored.size(); ++i) {
    appendGrasp(*stored[i], i, g);
    for (const Contact& k : stored[i]->grasp->contacts) {
      g.contact_points.row(static_cast<Eigen::Index>(c)) = k.point.transpose();
      g.contact_normals.row(static_cast<Eigen::Index>(c)) = k.normal.normalized().transpose();
      g.contact_depths.push_back(k.depth);
      g.contact_links.push_back(k.link);
      ++c;
    }
  }

  if (options.cluster && stored.size() >= 2 && !interrupted) {
    const auto t_cluster = Clock::now();
    std::vector<Pose> poses;
    poses.reserve(stored.size());
    for (std::size_t i = 0; i < stored.size(); ++i) poses.push_back(g.poseAt(i));
    ClusteringOptions co = options.clustering;
    co.rotation_scale = rho;
    map.clustering = clusterGrasps(poses, g.epsilon, co);
    result.timing.clustering_seconds = secondsSince(t_cluster);
  }

  if (interrupted) {
    result.status = BuildStatus::kInterrupted;
    result.message = "interrupted after " + std::to_string(trials) + " trials with " +
                     std::to_string(valid) + " force-closure grasps";
  } else if (stored.empty()) {
    result.status = BuildStatus::kNoGrasps;
    result.message = detail::noGraspMessage(map.sampling.outcomes, trials, object, hand);
  } else if (valid < options.valid_target) {
    result.status = BuildStatus::kTrialBudgetExhausted;
    result.message = "trial budget of " + std::to_string(options.max_trials) + " spent: found " +
                     std::to_string(valid) + " of " + std::to_string(options.valid_target) +
                     " force-closure grasps";
  } else {
    result.status = BuildStatus::kComplete;
    result.message = "found " + std::to_string(valid) + " force-closure grasps in " +
                     std::to_string(trials) + " trials";
  }
  result.timing.wall_seconds = secondsSince(t_start);
  return result;
}

}  // namespace taskmap
