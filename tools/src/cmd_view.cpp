// taskmap view FILE [-o page.html]: a task map (hands posed on the object, clusters, contacts)
// or a reaching trajectory (`reach -o`, the movement with a time slider, the map's hand closing
// on the object) as one self-contained interactive HTML page (taskmap::viz; three.js inlined,
// opens offline).
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "command.hpp"
#include "map_hand_cli.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/mapstore/trajectory_file.hpp"
#include "taskmap/viz/map_page.hpp"
#include "taskmap/viz/reach_page.hpp"

namespace taskmap::cli {
namespace {

struct ViewArgs {
  std::string file, output, hand;
  PageOptions page;
  bool quiet = false;
};

std::string defaultOutput(const std::string& file) {
  return std::filesystem::path(file).filename().replace_extension(".html").string();
}

void viewMap(const TaskMapData& map, const ViewArgs& args, const std::string& out) {
  MapHandResult found = findCommandMapHand(map, args.hand);
  if (!found.hand)
    std::cerr << "taskmap view: warning: drawing palms only: " << found.message << "\n";
  const std::optional<HandModel>& hand = found.hand;
  MapPageInput input;
  input.map = &map;
  input.hand = hand ? &*hand : nullptr;
  input.source = std::filesystem::path(args.file).filename().string();
  writeMapPage(input, out, args.page);
  if (!args.quiet)
    std::cout << "taskmap view: " << out << " (" << map.grasps.size() << " grasps"
              << (hand ? ", hand " + hand->name() : std::string(", palms only")) << ", "
              << std::filesystem::file_size(out) / 1024 << " KiB)\n";
}

void viewReach(const ViewArgs& args, const std::string& out) {
  const TrajectoryRecord r = readTrajectory(args.file);
  const TrajectoryHand found = findTrajectoryHand(r, commandHandOptions(args.hand));
  ReachPageInput input;
  input.trajectory = &r;
  if (found.found.hand) {
    input.hand = &*found.found.hand;
    input.grasp_joints = found.grasp_joints;
  } else {
    input.note = found.found.message;
    std::cerr << "taskmap view: warning: drawing the hand as the planner's collision primitives: "
              << found.found.message
              << (found.found.status == MapHandResult::Status::kNotFound ? " (give --hand)" : "")
              << "\n";
  }
  writeReachPage(input, out, args.page);
  if (!args.quiet)
    std::cout << "taskmap view: " << out << " (trajectory, " << r.rows() << " steps, "
              << (input.hand ? "hand " + input.hand->name() + " closing to grasp " +
                                   std::to_string(r.grasp_index)
                             : std::string("hand as primitives"))
              << ", " << std::filesystem::file_size(out) / 1024 << " KiB)\n";
}

void runView(const ViewArgs& args) {
  if (!std::filesystem::exists(args.file))
    throw Error("file '" + args.file + "' does not exist; give a task map or a trajectory (.h5)");
  args.page.validate();
  const std::string out = args.output.empty() ? defaultOutput(args.file) : args.output;
  std::optional<TaskMapData> map;
  try {
    map = readMap(args.file);
  } catch (const Error& e) {
    if (std::string(e.what()).find("not a task map") == std::string::npos) throw;
  }
  if (map) return viewMap(*map, args, out);
  viewReach(args, out);
}

const CommandRegistrar kRegistrar(
    "view", "Write an interactive 3-D page (HTML) of a map or a reach trajectory",
    [](CLI::App& app) {
      auto args = std::make_shared<ViewArgs>();
      CLI::App* cmd = app.add_subcommand(
          "view",
          "Write an interactive 3-D page (one self-contained HTML file, opens offline in a "
          "browser) of a task map (the hand's collision shapes posed by each grasp on the object, "
          "coloured by cluster; filters, contacts, ghosts) or of a trajectory file from `reach "
          "-o` (the movement with a time slider and the cost terms; the map's hand closes to the "
          "chosen grasp at the end).");
      cmd->add_option("file", args->file, "task map or trajectory file (.h5)")->required();
      cmd->add_option("-o,--output", args->output,
                      "HTML file to write (default: <file stem>.html)");
      cmd->add_option("--hand", args->hand,
                      "hand URDF or bundled name to draw a map's grasps or a trajectory's grasp "
                      "with (default: the map's recorded or bundled hand, found by its SHA-256)");
      cmd->add_option("--ghosts", args->page.ghost_limit,
                      "most hands drawn at once as ghosts (the other grasps are palm glyphs)")
          ->capture_default_str();
      cmd->add_option("--title", args->page.title, "page title");
      cmd->add_flag("-q,--quiet", args->quiet, "print nothing on success");
      cmd->callback([args] { runView(*args); });
    });

}  // namespace
}  // namespace taskmap::cli
