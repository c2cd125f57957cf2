// taskmap inspect MAP.h5 [--json] [--png OUT.png]: summary and picture of a task map.
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "command.hpp"
#include "map_hand_cli.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/inspect/map_summary.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/picture/map_picture.hpp"

namespace taskmap::cli {
namespace {

struct InspectArgs {
  std::string map;
  bool json = false;
  std::string png;
  PictureOptions picture;
  std::string hand;
  bool force = false;
};

void runInspect(const InspectArgs& args) {
  InspectOptions options;
  options.map = args.map;
  options.validate();
  if (!args.png.empty()) args.picture.validate();
  checkOutputPath(args.png, {args.map}, OutputKind::kPng, args.force, "--png");
  const InspectResult r = inspectMap(options);
  if (args.json) {
    std::cout << summaryJson(r.summary) << "\n";
  } else {
    std::cout << formatSummary(r.summary);
  }
  if (!args.png.empty()) {
    const std::optional<HandModel> hand = mapHand(r.map, args.hand, "taskmap inspect");
    writeMapPicture(r.map, r.summary, args.png, args.picture, hand ? &*hand : nullptr);
    if (!args.json) std::cout << "picture    " << args.png << "\n";
  }
}

const CommandRegistrar kRegistrar(
    "inspect", "Summarise a map (outcomes, epsilon, clusters) and draw it (--png)",
    [](CLI::App& app) {
      auto args = std::make_shared<InspectArgs>();
      CLI::App* cmd =
          app.add_subcommand("inspect",
                             "Summarise a task map: object, hand, sampling, trial outcomes, "
                             "epsilon statistics and the "
                             "cluster table (--json for scripts), and optionally draw it (--png).");
      cmd->add_option("map", args->map, "task map file (.h5)")->required();
      cmd->add_flag("--json", args->json,
                    "print JSON instead of text: keys path, generator, created_utc, object, hand, "
                    "sampling, grasps, epsilon (over force-closure grasps), clustering (null or "
                    "{linkage, threshold, min_size, outliers, clusters[{id, size, representative, "
                    "pose [x y z qw qx qy qz], approach, mean_epsilon, best_epsilon, color}]})");
      cmd->add_option(
          "--png", args->png,
          "also draw the map to this PNG: three orthographic views (top, front, side) "
          "of the object silhouette with palm positions coloured by cluster (outliers "
          "grey), representatives with their approach axis (palm +z) and the outline of "
          "the hand posed by them, and a histogram of epsilon per cluster");
      cmd->add_option("--hand", args->hand,
                      "--png: the hand to outline (URDF or bundled hand name; default: the map's "
                      "hand, found by its URDF SHA-256; without it no hand is drawn)");
      cmd->add_option("--width", args->picture.width, "picture width in pixels (>= 800)")
          ->capture_default_str();
      cmd->add_option("--height", args->picture.height, "picture height in pixels (>= 600)")
          ->capture_default_str();
      cmd->add_flag("--force", args->force, "replace an existing --png file that is not a PNG");
      cmd->callback([args]() { runInspect(*args); });
    });

}  // namespace
}  // namespace taskmap::cli
