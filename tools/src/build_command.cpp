// The build command line shared by `taskmap build` and `taskmap-mpi build`.
#include "build_command.hpp"

#include <filesystem>
#include <iostream>
#include <type_traits>
#include <utility>
#include <vector>

#include "taskmap/builder/build_report.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/inspect/hand_check.hpp"
#include "taskmap/sampler/sampler.hpp"

namespace taskmap::cli {
void addBuildOptions(CLI::App& cmd_ref, BuildArgs& args) {
  CLI::App* cmd = &cmd_ref;
  cmd->add_option("--object", args.object,
                  "object mesh (any format assimp reads), or a bundled object name (basket, "
                  "bowl, box, cylinder, mug, sphere)")
      ->required();
  cmd->add_option("--hand", args.hand,
                  "hand URDF or MJCF (with its <stem>.hand.json sidecar), or a bundled "
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

namespace {

/// Declares one knob as a CLI11 option (a flag for a bool) with its help and checks.
struct KnobDeclarer {
  CLI::App* cmd;
  template <class T>
  void operator()(const KnobInfo& info, T& field) const {
    const std::string name = knobName(info.name, KnobStyle::kCommandLine);
    if constexpr (std::is_same_v<T, bool>) {
      cmd->add_flag(name, field, info.help);
    } else {
      CLI::Option* o = cmd->add_option(name, field, info.help);
      if (!info.choices.empty()) o->check(CLI::IsMember(info.choices));
      if (info.check == KnobCheck::kPositive) o->check(CLI::PositiveNumber);
      if (info.check == KnobCheck::kNonNegative) o->check(CLI::NonNegativeNumber);
      if (info.check == KnobCheck::kRange) {
        if constexpr (std::is_integral_v<T>)
          o->check(CLI::Range(static_cast<T>(info.min), static_cast<T>(info.max)));
        else
          o->check(CLI::Range(info.min, info.max));
      }
      if (info.capture_default) o->capture_default_str();
    }
  }
};

}  // namespace

void addBuildKnobs(CLI::App& cmd_ref, BuildArgs& args) {
  CLI::App* cmd = &cmd_ref;
  visitBuildKnobs(static_cast<BuildKnobs&>(args), KnobDeclarer{cmd});
  addPackagePathOption(cmd);
  cmd->add_flag("-q,--quiet", args.quiet, "no progress and no summary");
  cmd->add_flag("--progress", args.progress, "draw the progress bar even when not a terminal");
}

BuildOptions knobOptions(const BuildArgs& args) {
  return buildOptionsOf(args, KnobStyle::kCommandLine);
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
  return holdValidationOf(args, KnobStyle::kCommandLine);
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
  if (!quiet) std::cerr << holdLabelsText(label, labels, keep_holding);
}

ProgressPrinter::ProgressPrinter(std::string label, bool terminal, bool quiet)
    : label_(std::move(label)), terminal_(terminal), quiet_(quiet) {}

void ProgressPrinter::operator()(const BuildProgress& p) {
  if (quiet_) return;
  if (!terminal_) {
    if (p.elapsed_seconds < next_log_) return;
    next_log_ = p.elapsed_seconds + 10.0;
  }
  std::cerr << buildProgressLine(p, label_, terminal_) << std::flush;
  drawn_ = drawn_ || terminal_;
}

void ProgressPrinter::finish() {
  if (drawn_) std::cerr << "\n";
  drawn_ = false;
}

void printBuildSummary(const std::string& label, const BuildArgs& args, const BuildResult& result,
                       double write_seconds, const std::string& how) {
  if (!args.quiet) std::cout << buildSummaryText(label, result, write_seconds, how, args.output);
  std::cerr << buildBudgetWarning(label, result);
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

}  // namespace taskmap::cli
