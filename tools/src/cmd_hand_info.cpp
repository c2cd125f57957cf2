// taskmap hand-info HAND [--png FILE] [--json]: what taskmap makes of a hand (URDF + sidecar):
// joints, limits, mimic couplings, preshape and closing, palm frame, approach axis, rho, and
// warnings about set-ups that cannot grasp; optionally a picture of the preshape and the
// closed hand in three views.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "build_command.hpp"
#include "command.hpp"
#include "mesh_options.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/inspect/hand_info.hpp"
#include "taskmap/picture/hand_picture.hpp"
#include "taskmap/viz/hand_page.hpp"

namespace taskmap::cli {
namespace {

struct HandInfoArgs {
  std::string hand, png, html;
  bool json = false;
  bool force = false;
};

void run(const HandInfoArgs& args) {
  const std::string urdf =
      std::filesystem::exists(args.hand) ? args.hand : bundledHandUrdf(args.hand);
  checkOutputPath(args.png, {urdf, handSidecarPath(urdf)}, OutputKind::kPng, args.force, "--png");
  const HandModel hand = HandModel::load(urdf);
  const HandInfo info = handInfo(hand);
  if (!args.png.empty()) writeHandPicture(hand, args.png);
  if (!args.html.empty()) writeHandPage(hand, args.html);
  std::fputs((args.json ? info.json + "\n" : info.text).c_str(), stdout);
  if (!args.png.empty() && !args.json) std::printf("wrote:          %s\n", args.png.c_str());
  if (!args.html.empty() && !args.json) std::printf("wrote:          %s\n", args.html.c_str());
}

const CommandRegistrar kRegistrar(
    "hand-info", "Show what taskmap makes of a hand; warn about set-ups that cannot grasp",
    [](CLI::App& app) {
      auto args = std::make_shared<HandInfoArgs>();
      CLI::App* cmd = app.add_subcommand(
          "hand-info",
          "Show what taskmap makes of a hand: joints, limits, mimic couplings, preshape and "
          "closing, "
          "palm frame, approach axis, rho; warn about set-ups that cannot grasp (no finger reaches "
          "past the front of the palm or of geometry fixed to it; collision meshes that could not "
          "be decomposed), the warnings `build` prints before its trials");
      cmd->add_option("hand", args->hand,
                      "hand URDF or MJCF (with its <stem>.hand.json) or bundled name")
          ->required();
      cmd->add_option("--png", args->png,
                      "also draw the hand in its preshape and fully closed, three views each");
      cmd->add_option("--html", args->html,
                      "also write an interactive 3-D page (self-contained HTML): the hand open and "
                      "closed, palm frame, approach axis, one slider per joint");
      cmd->add_flag("--json", args->json, "print JSON instead of text");
      addPackagePathOption(cmd);
      cmd->add_flag("--force", args->force, "replace an existing --png file that is not a PNG");
      cmd->callback([args]() { run(*args); });
    });

}  // namespace
}  // namespace taskmap::cli
