// taskmap build: sample, simulate and score grasp trials on all cores and write
// a task map.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "command.hpp"
#include "data_dir.hpp"
#include "mesh_options.hpp"
#include "taskmap/builder/map_builder.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap::cli {
namespace {

std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free, "signal handler needs a lock-free flag");

extern "C" void onStopSignal(int sig) {
  g_stop.store(true);
  // A second Ctrl-C kills at once (the output path is still safe: written via
  // rename).
  std::signal(sig, SIG_DFL);
}

struct BuildArgs {
  std::string object, hand, output, sampler = "mixed";
  double scale = 1.0;
  std::uint64_t valid = 1000, trials = 200000, seed = 1;
  int threads = 0;
  double friction = 0.5;
  int cone_edges = 8;
  bool keep_invalid = false, no_cluster = false, quiet = false, progress = false;
  bool timestamp = false;
  MeshRepairArgs repair;
};

// Hand argument: a URDF path, or the name of a bundled hand (<data dir>/hands/<name>/).
std::string resolveHand(const std::string& hand) {
  if (std::filesystem::exists(hand)) return hand;
  return bundledHandUrdf(hand);
}

std::string clock(double seconds) {
  if (!(seconds >= 0.0) || seconds > 359999.0) return "--:--:--";
  const auto s = static_cast<long>(seconds + 0.5);
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%02ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  return buffer;
}

// Progress: a bar on a terminal, a log line every 10 s otherwise.
class ProgressPrinter {
 public:
  ProgressPrinter(bool terminal, bool quiet) : terminal_(terminal), quiet_(quiet) {}

  void operator()(const BuildProgress& p) {
    if (quiet_) return;
    const double rate = p.elapsed_seconds > 0 ? p.trials_done / p.elapsed_seconds : 0.0;
    const std::uint64_t valid = std::min(p.valid_found, p.valid_target);
    const double by_valid = static_cast<double>(valid) / static_cast<double>(p.valid_target);
    const double by_trials = static_cast<double>(p.trials_done) / static_cast<double>(p.max_trials);
    const double fraction = std::min(1.0, std::max(by_valid, by_trials));
    const double eta = fraction > 0 ? p.elapsed_seconds * (1.0 - fraction) / fraction : -1.0;
    char line[256];
    if (terminal_) {
      constexpr int kWidth = 30;
      const int filled = static_cast<int>(fraction * kWidth);
      std::string bar(static_cast<std::size_t>(filled), '#');
      bar.resize(kWidth, '-');
      std::snprintf(line, sizeof line,
                    "\r[%s] %3.0f%%  trials %llu  valid %llu/%llu  %.0f "
                    "trials/s  ETA %s ",
                    bar.c_str(), 100.0 * fraction, static_cast<unsigned long long>(p.trials_done),
                    static_cast<unsigned long long>(valid),
                    static_cast<unsigned long long>(p.valid_target), rate, clock(eta).c_str());
      std::cerr << line << std::flush;
      drawn_ = true;
    } else if (p.elapsed_seconds >= next_log_) {
      next_log_ = p.elapsed_seconds + 10.0;
      std::snprintf(line, sizeof line,
                    "taskmap build: %s elapsed, %llu trials, %llu/%llu valid, "
                    "%.0f trials/s, "
                    "ETA %s\n",
                    clock(p.elapsed_seconds).c_str(),
                    static_cast<unsigned long long>(p.trials_done),
                    static_cast<unsigned long long>(valid),
                    static_cast<unsigned long long>(p.valid_target), rate, clock(eta).c_str());
      std::cerr << line << std::flush;
    }
  }
  void finish() {
    if (drawn_) std::cerr << "\n";
    drawn_ = false;
  }

 private:
  bool terminal_, quiet_, drawn_ = false;
  double next_log_ = 10.0;
};

std::string percent(double part, double whole) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f%%", whole > 0 ? 100.0 * part / whole : 0.0);
  return buffer;
}

// The summary printed after a written build.
std::string summaryOf(const BuildResult& result, const BuildArgs& args, double write_seconds) {
  const TaskMapData& map = result.map;
  const BuildTiming& t = result.timing;
  std::ostringstream os;
  os << "taskmap build: " << toString(result.status) << ": " << result.message << "\n";
  os << "  object    " << map.object.name << " (" << map.object.vertices.rows()
     << " vertices, scale " << map.object.scale << "), hand " << map.hand.name << "\n";
  os << "  outcomes ";
  for (const auto& [name, count] : map.sampling.outcomes) os << " " << name << " " << count;
  os << "\n";
  os << "  stored    " << map.grasps.size() << " grasps";
  if (map.clustering) {
    std::size_t outliers = 0;
    for (int l : map.clustering->labels) outliers += l < 0;
    os << ", " << map.clustering->clusters.size() << " clusters (" << outliers << " outliers)";
  }
  os << "\n";
  const int threads = args.threads > 0
                          ? args.threads
                          : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  os << "  threads   " << threads << " (not stored: the map does not depend on it)\n";
  const double stages = t.sampling_seconds + t.simulation_seconds + t.quality_seconds;
  const double trial_wall = t.wall_seconds - t.setup_seconds - t.clustering_seconds;
  char line[512];
  std::snprintf(line, sizeof line,
                "  time      wall %.2f s: setup %.2f s, trials %.2f s (%llu simulated, %.1f "
                "trials/s), clustering %.2f s, writing %.2f s\n"
                "  work      sampling %s, simulation %s, quality %s (CPU seconds %.2f)\n",
                t.wall_seconds + write_seconds, t.setup_seconds, trial_wall,
                static_cast<unsigned long long>(t.trials_simulated),
                trial_wall > 0 ? static_cast<double>(t.trials_simulated) / trial_wall : 0.0,
                t.clustering_seconds, write_seconds, percent(t.sampling_seconds, stages).c_str(),
                percent(t.simulation_seconds, stages).c_str(),
                percent(t.quality_seconds, stages).c_str(), stages);
  os << line;
  os << "  wrote     " << args.output << "\n";
  return os.str();
}

void runBuild(const BuildArgs& args) {
  BuildOptions options;
  options.sampler.kind = samplerKindFromString(args.sampler);
  options.valid_target = args.valid;
  options.max_trials = args.trials;
  options.seed = args.seed;
  options.threads = args.threads;
  options.quality.friction = args.friction;
  options.quality.cone_edges = args.cone_edges;
  options.keep_invalid = args.keep_invalid;
  options.cluster = !args.no_cluster;
  if (!(args.scale > 0.0)) throw Error("--scale must be positive");
  if (args.output.empty()) throw Error("-o MAP.h5 is required");
  const std::filesystem::path out_dir = std::filesystem::absolute(args.output).parent_path();
  if (!std::filesystem::is_directory(out_dir))
    throw Error("output directory '" + out_dir.string() + "' does not exist; create it first");
  const std::string hand_path = resolveHand(args.hand);
  MeshLoadOptions load;
  load.scale = args.scale;
  applyMeshRepairArgs(args.repair, load);
  nlohmann::json extra = {{"object", args.object}, {"scale", args.scale}, {"hand", hand_path}};
  if (load.wrap)
    extra["repair"] = {{"wrap", true}, {"alpha", load.wrap_alpha}, {"offset", load.wrap_offset}};
  if (!load.repair) extra["repair"] = false;
  options.extra_params_json = extra.dump();
  options.validate();

  const ObjectModel object = ObjectModel::load(args.object, load);
  const HandModel hand = HandModel::load(hand_path);

  g_stop.store(false);
  struct sigaction action {};
  action.sa_handler = onStopSignal;
  sigemptyset(&action.sa_mask);
  struct sigaction old_int {
  }, old_term{};
  sigaction(SIGINT, &action, &old_int);
  sigaction(SIGTERM, &action, &old_term);

  ProgressPrinter printer(::isatty(STDERR_FILENO) != 0 || args.progress, args.quiet);
  BuildResult result;
  try {
    result = buildMap(
        object, hand, options, [&printer](const BuildProgress& p) { printer(p); }, &g_stop);
  } catch (...) {
    printer.finish();
    sigaction(SIGINT, &old_int, nullptr);
    sigaction(SIGTERM, &old_term, nullptr);
    throw;
  }
  printer.finish();
  if (result.status == BuildStatus::kInterrupted) {
    sigaction(SIGINT, &old_int, nullptr);
    sigaction(SIGTERM, &old_term, nullptr);
    std::cerr << "taskmap build: " << result.message << "; nothing written to '" << args.output
              << "'\n";
    exitCode() = 130;
    return;
  }
  if (result.status == BuildStatus::kNoGrasps) {
    sigaction(SIGINT, &old_int, nullptr);
    sigaction(SIGTERM, &old_term, nullptr);
    std::cerr << "taskmap build: error: " << result.message << "; nothing written to '"
              << args.output << "'\n";
    exitCode() = 3;
    return;
  }
  if (args.timestamp) result.map.created_utc = mapCreationTime(true);
  const auto t_write = std::chrono::steady_clock::now();
  writeMap(args.output,
           result.map);  // signals stay caught: the write is never cut short
  const double write_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t_write).count();
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);

  if (!args.quiet) std::cout << summaryOf(result, args, write_seconds);
  if (result.status == BuildStatus::kTrialBudgetExhausted)
    std::cerr << "taskmap build: warning: " << result.message
              << "; raise --trials or check the object and hand\n";
}

const CommandRegistrar kRegistrar("build", [](CLI::App& app) {
  auto args = std::make_shared<BuildArgs>();
  CLI::App* cmd =
      app.add_subcommand("build",
                         "Build a task map: sample initial hand poses, simulate each "
                         "grasp trial (retract, close, "
                         "squeeze), score force closure, cluster the grasps, and write "
                         "an HDF5 map "
                         "(mapstore/SCHEMA.md). The same command and seed give the same "
                         "map for any --threads.");
  cmd->add_option("--object", args->object, "object mesh (any format assimp reads)")->required();
  cmd->add_option("--hand", args->hand,
                  "hand URDF (with its <stem>.hand.json sidecar), or a bundled "
                  "hand name")
      ->required();
  cmd->add_option("-o,--output", args->output, "task map to write (.h5)")->required();
  cmd->add_option("--scale", args->scale, "multiplies the mesh coordinates (file units -> m)")
      ->capture_default_str();
  cmd->add_option("--sampler", args->sampler,
                  "initial poses: volume (paper: point inside, uniform "
                  "orientation), surface "
                  "(approach along the inward normal of an area-weighted "
                  "surface point, random "
                  "roll and standoff; finds handles), mixed (even trials "
                  "volume, odd surface)")
      ->check(CLI::IsMember({"volume", "surface", "mixed"}))
      ->capture_default_str();
  cmd->add_option("--valid", args->valid, "stop after this many force-closure grasps")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--trials", args->trials, "trial budget")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "random seed")->capture_default_str();
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  cmd->add_option("--friction", args->friction, "Coulomb friction coefficient mu")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--cone-edges", args->cone_edges, "friction cone edges")
      ->check(CLI::Range(3, 64))
      ->capture_default_str();
  addMeshRepairOptions(cmd, args->repair);
  cmd->add_flag("--keep-invalid", args->keep_invalid,
                "store every simulated grasp (status ok), not only force-closure ones");
  cmd->add_flag("--no-cluster", args->no_cluster, "do not cluster the grasps");
  cmd->add_flag("--timestamp", args->timestamp,
                "store the current time as created_utc (default: SOURCE_DATE_EPOCH if set, "
                "else none, so the same arguments give the same bytes)");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress and no summary");
  cmd->add_flag("--progress", args->progress, "draw the progress bar even when not a terminal");
  cmd->callback([args]() { runBuild(*args); });
});

}  // namespace
}  // namespace taskmap::cli
