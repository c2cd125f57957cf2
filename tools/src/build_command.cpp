// The build command line shared by `taskmap build` and `taskmap-mpi build`.
#include "build_command.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/inspect/hand_check.hpp"
#include "taskmap/sampler/sampler.hpp"

namespace taskmap::cli {
namespace {

std::string percent(double part, double whole) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1f%%", whole > 0 ? 100.0 * part / whole : 0.0);
  return buffer;
}

}  // namespace

void addBuildOptions(CLI::App& cmd_ref, BuildArgs& args) {
  CLI::App* cmd = &cmd_ref;
  cmd->add_option("--object", args.object, "object mesh (any format assimp reads)")->required();
  cmd->add_option("--hand", args.hand,
                  "hand URDF (with its <stem>.hand.json sidecar), or a bundled "
                  "hand name")
      ->required();
  cmd->add_option("-o,--output", args.output, "task map to write (.h5)")->required();
  cmd->add_option("--scale", args.scale, "multiplies the mesh coordinates (file units -> m)")
      ->capture_default_str();
  addMeshRepairOptions(cmd, args.repair);
  addBuildKnobs(*cmd, args);
  cmd->add_flag("--force", args.force,
                "replace an existing output file that is not a task map (never one of the "
                "inputs)");
}

void addBuildKnobs(CLI::App& cmd_ref, BuildArgs& args) {
  CLI::App* cmd = &cmd_ref;
  cmd->add_option("--sampler", args.sampler,
                  "initial poses: volume (paper: point inside, uniform "
                  "orientation), surface "
                  "(approach along the inward normal of an area-weighted "
                  "surface point, random "
                  "roll and standoff; finds handles), mixed (even trials "
                  "volume, odd surface), antipodal (parallel jaws: the pads on two surface "
                  "points whose normals lie in each other's friction cones), enclose (palm on a "
                  "surface point, no open finger inside the object), antipodal_palm (parallel "
                  "jaws: an antipodal pair, the palm placed where it meets the surface behind "
                  "it, no open finger inside the object)")
      ->check(
          CLI::IsMember({"volume", "surface", "mixed", "antipodal", "enclose", "antipodal_palm"}))
      ->capture_default_str();
  cmd->add_option("--valid", args.valid, "stop after this many force-closure grasps")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--trials", args.trials, "trial budget")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--seed", args.seed, "random seed")->capture_default_str();
  cmd->add_option("--threads", args.threads, "worker threads (0 = all cores)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  cmd->add_option("--friction", args.friction, "Coulomb friction coefficient mu")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--cone-edges", args.cone_edges, "friction cone edges")
      ->check(CLI::Range(3, 64))
      ->capture_default_str();
  cmd->add_option("--volume", args.volume,
                  "wrench-space volume of the stored grasps: never (force closure and epsilon "
                  "only; the volume needs the whole 6-D hull, most of the quality time on fine "
                  "meshes), force_closure (every stored grasp: the builds before issue 33), "
                  "always")
      ->check(CLI::IsMember({"never", "force_closure", "always"}))
      ->capture_default_str();
  cmd->add_option("--contacts-per-link", args.contacts_per_link,
                  "reduce each link's contacts to at most this many representatives before the "
                  "wrench hull (docs/METHOD.md 4; changes force-closure verdicts), 0 = all")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  cmd->add_option("--grasp", args.grasp,
                  "palm: the approach stops when the palm touches, the palm is pressed "
                  "(power grasps); fingertip: it stops at the first contact or when the palm "
                  "is --standoff from the object, no palm contact needed (pinch grasps). "
                  "Default: the hand sidecar's grasp.mode (palm)")
      ->check(CLI::IsMember({"palm", "fingertip"}));
  cmd->add_option("--standoff", args.standoff,
                  "fingertip grasps: palm-to-object distance where the approach stops, metres "
                  "(default: the hand sidecar's grasp.standoff, else a tenth of the hand's "
                  "palm-to-fingertip length, which keeps the palm off the object)")
      ->check(CLI::Range(0.0, 0.5));
  cmd->add_flag("--allow-size", args.allow_size,
                "build an object whose size is implausible for the hand (over 20 times its "
                "reach, or thinner than its thinnest finger link), refused by default as a "
                "file in other units");
  addPackagePathOption(cmd);
  cmd->add_flag("--keep-invalid", args.keep_invalid,
                "store every simulated grasp (status ok), not only force-closure ones");
  cmd->add_flag("--no-cluster", args.no_cluster, "do not cluster the grasps");
  cmd->add_flag("--validate", args.validate,
                "label every stored grasp with the physics hold test before writing "
                "(taskmap validate; docs/VALIDATION.md)");
  cmd->add_flag("--keep-holding", args.keep_holding,
                "with --validate: store only the grasps that hold in the physics test (the "
                "others are dropped before clustering)");
  cmd->add_flag("--hold-filter", args.hold_filter,
                "store only grasps whose squeeze the hold filter finds balanced: the "
                "position-controlled hand presses the free object into equilibrium and resists "
                "1 N pushes (docs/METHOD.md 4b; costs trials)");
  cmd->add_flag("--timestamp", args.timestamp,
                "store the current time as created_utc (default: SOURCE_DATE_EPOCH if set, "
                "else none, so the same arguments give the same bytes)");
  cmd->add_flag("-q,--quiet", args.quiet, "no progress and no summary");
  cmd->add_flag("--progress", args.progress, "draw the progress bar even when not a terminal");
}

BuildOptions knobOptions(const BuildArgs& args) {
  BuildOptions options;
  options.sampler.kind = samplerKindFromString(args.sampler);
  options.valid_target = args.valid;
  options.max_trials = args.trials;
  options.seed = args.seed;
  options.threads = args.threads;
  options.quality.friction = args.friction;
  options.quality.cone_edges = args.cone_edges;
  options.quality.volume = volumeModeFromString(args.volume);
  options.quality.contacts_per_link = args.contacts_per_link;
  options.keep_invalid = args.keep_invalid;
  options.cluster = !args.no_cluster;
  options.hold_filter.enabled = args.hold_filter;
  options.check_size = !args.allow_size;
  if (args.grasp == "palm")
    options.simulation.grasp_mode = GraspMode::kPalm;
  else if (args.grasp == "fingertip")
    options.simulation.grasp_mode = GraspMode::kFingertip;
  options.simulation.standoff = args.standoff;
  return options;
}

MeshLoadOptions meshLoadOptions(const BuildArgs& args) {
  MeshLoadOptions load;
  load.scale = args.scale;
  applyMeshRepairArgs(args.repair, load);
  return load;
}

bool printHandWarnings(const std::string& label, const HandModel& hand) {
  const std::vector<std::string> warnings = checkHand(hand).warnings;
  for (const std::string& w : warnings)
    std::cerr << label << ": warning: hand '" << hand.name() << "': " << w << "\n";
  return !warnings.empty();
}

HoldValidation holdValidation(const BuildArgs& args) {
  if (args.keep_holding && !args.validate)
    throw Error("--keep-holding needs --validate (the hold labels decide what is kept)");
  if (!args.validate) return HoldValidation::kOff;
  return args.keep_holding ? HoldValidation::kKeepHolding : HoldValidation::kLabel;
}

FileBuildOptions fileBuildOptions(const BuildArgs& args) {
  FileBuildOptions o;
  o.object = args.object;
  o.hand = args.hand;
  o.output = args.output;
  o.build = knobOptions(args);
  o.validation = holdValidation(args);
  o.mesh = meshLoadOptions(args);
  o.timestamp = args.timestamp;
  o.force = args.force;
  return o;
}

void printHoldLabels(const std::string& label, const std::optional<HoldLabels>& labels,
                     bool keep_holding, bool quiet) {
  if (!labels || quiet) return;
  const HoldLabels& s = *labels;
  char line[200];
  std::snprintf(
      line, sizeof line,
      "%s: physics validation: %zu of %zu grasps hold (%.1f %%), %.1f grasps per "
      "CPU-second\n",
      label.c_str(), s.holding, s.tested,
      s.tested ? 100.0 * static_cast<double>(s.holding) / static_cast<double>(s.tested) : 0.0,
      s.cpu_seconds > 0 ? static_cast<double>(s.tested) / s.cpu_seconds : 0.0);
  std::cerr << line;
  if (keep_holding)
    std::cerr << label << ": --keep-holding: kept " << s.kept << " of " << s.before
              << " grasps (the others do not hold)\n";
}

std::string clockString(double seconds) {
  if (!(seconds >= 0.0) || seconds > 359999.0) return "--:--:--";
  const auto s = static_cast<long>(seconds + 0.5);
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%02ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  return buffer;
}

ProgressPrinter::ProgressPrinter(std::string label, bool terminal, bool quiet)
    : label_(std::move(label)), terminal_(terminal), quiet_(quiet) {}

void ProgressPrinter::operator()(const BuildProgress& p) {
  if (quiet_) return;
  const double rate = p.elapsed_seconds > 0 ? p.trials_done / p.elapsed_seconds : 0.0;
  const std::uint64_t valid = std::min(p.valid_found, p.valid_target);
  const double by_valid = static_cast<double>(valid) / static_cast<double>(p.valid_target);
  const double by_trials = static_cast<double>(p.trials_done) / static_cast<double>(p.max_trials);
  const double fraction = std::min(1.0, std::max(by_valid, by_trials));
  const double eta = fraction > 0 ? p.elapsed_seconds * (1.0 - fraction) / fraction : -1.0;
  char blocks[64] = "";
  if (p.blocks_total > 0)
    std::snprintf(blocks, sizeof blocks, "blocks %llu/%llu  ",
                  static_cast<unsigned long long>(p.blocks_done),
                  static_cast<unsigned long long>(p.blocks_total));
  char line[320];
  if (terminal_) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(fraction * kWidth);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '-');
    std::snprintf(line, sizeof line,
                  "\r[%s] %3.0f%%  %strials %llu  valid %llu/%llu  %.0f "
                  "trials/s  ETA %s ",
                  bar.c_str(), 100.0 * fraction, blocks,
                  static_cast<unsigned long long>(p.trials_done),
                  static_cast<unsigned long long>(valid),
                  static_cast<unsigned long long>(p.valid_target), rate, clockString(eta).c_str());
    std::cerr << line << std::flush;
    drawn_ = true;
  } else if (p.elapsed_seconds >= next_log_) {
    next_log_ = p.elapsed_seconds + 10.0;
    std::snprintf(line, sizeof line,
                  "%s: %s elapsed, %s%llu trials, %llu/%llu valid, "
                  "%.0f trials/s, "
                  "ETA %s\n",
                  label_.c_str(), clockString(p.elapsed_seconds).c_str(), blocks,
                  static_cast<unsigned long long>(p.trials_done),
                  static_cast<unsigned long long>(valid),
                  static_cast<unsigned long long>(p.valid_target), rate, clockString(eta).c_str());
    std::cerr << line << std::flush;
  }
}
void ProgressPrinter::finish() {
  if (drawn_) std::cerr << "\n";
  drawn_ = false;
}

void printBuildSummary(const std::string& label, const BuildArgs& args, const BuildResult& result,
                       double write_seconds, const std::string& how) {
  const TaskMapData& map = result.map;
  const BuildTiming& t = result.timing;
  std::ostringstream os;
  os << label << ": " << toString(result.status) << ": " << result.message << "\n";
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
  os << "  threads   " << how << "\n";
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
  if (!args.quiet) std::cout << os.str();
  if (result.status == BuildStatus::kTrialBudgetExhausted)
    std::cerr << label << ": warning: " << result.message
              << "; raise --trials or check the object and hand\n";
}

void addDatasetOptions(CLI::App& cmd, DatasetArgs& args) {
  cmd.add_option("--objects", args.objects,
                 "text file naming one mesh a line (relative to the file; # comments), "
                 "optionally followed by its scale (file units to metres), e.g. "
                 "\"bunny.ply 0.01\"; without one a mesh takes --scale")
      ->required();
  cmd.add_option("--hands", args.hands, "comma-separated hand URDFs or bundled hand names")
      ->required();
  cmd.add_option("-o,--output", args.output, "directory for the maps and manifest.json")
      ->required();
  cmd.add_option("--scale", args.scale,
                 "multiplies the coordinates of every mesh the list gives no scale (file units "
                 "-> m)")
      ->capture_default_str();
  addBuildKnobs(cmd, args.knobs);
  cmd.add_flag("--force", args.knobs.force,
               "replace existing map files (and manifest.json) in the directory that are not "
               "taskmap files (never an input)");
}

DatasetOptions datasetOptions(const DatasetArgs& args) {
  DatasetOptions o;
  o.objects = args.objects;
  o.hands = args.hands;
  o.output = args.output;
  o.scale = args.scale;
  o.build = knobOptions(args.knobs);
  o.timestamp = args.knobs.timestamp;
  o.validation = holdValidation(args.knobs);
  o.force = args.knobs.force;
  return o;
}

std::string datasetProgressLine(std::size_t done, std::size_t total, double elapsed_seconds,
                                const DatasetEntry& e) {
  const double eta =
      done > 0 ? elapsed_seconds / static_cast<double>(done) * static_cast<double>(total - done)
               : -1.0;
  std::string line = "[" + std::to_string(done) + "/" + std::to_string(total) + ", ETA " +
                     clockString(eta) + "] " + e.object + " x " + e.hand + ": " +
                     toString(e.status);
  if (e.status == DatasetJobStatus::kFailed) return line + ": " + e.error.value_or("");
  return line + ", " + std::to_string(e.valid.value_or(0)) + " valid in " +
         std::to_string(e.trials.value_or(0)) + " trials -> " + e.file;
}

}  // namespace taskmap::cli
