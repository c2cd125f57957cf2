// taskmap hand-init: drafts a hand sidecar from the URDF alone (hands/hand_draft.hpp) and
// prints each guess and why.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "command.hpp"
#include "mesh_options.hpp"
#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/hands/hand_draft.hpp"

namespace taskmap::cli {
namespace {

struct HandInitArgs {
  std::string urdf;
  std::string output;  ///< sidecar to write; empty: print it
  bool force = false;
};

void run(const HandInitArgs& args) {
  if (!std::filesystem::exists(args.urdf))
    throw Error("hand-init: no URDF file '" + args.urdf + "'");
  if (!args.output.empty() && std::filesystem::exists(args.output) && !args.force)
    throw Error("hand-init: '" + args.output +
                "' exists; give --force to replace it (or another -o)");
  const SidecarDraft d = draftHandSidecar(args.urdf);
  for (const std::string& n : d.notes) std::printf("guess: %s\n", n.c_str());
  if (!d.undecided.empty()) {
    for (const std::string& u : d.undecided) std::printf("undecided: %s\n", u.c_str());
    throw Error("hand-init: could not draft a sidecar for '" + args.urdf +
                "': write the undecided fields by hand (meshes/hands/README.md)");
  }
  if (args.output.empty()) {
    std::cout << d.json;
    return;
  }
  writeFileAtomically(args.output, d.json, "cannot write sidecar '" + args.output + "'");
  std::printf(
      "wrote: %s (the draft loads with this hand; build with --hand %s after renaming it "
      "to <stem>.hand.json beside it, or check it with hand-info)\n",
      args.output.c_str(), args.urdf.c_str());
}

const CommandRegistrar kRegistrar(
    "hand-init", "Draft a hand's sidecar (<stem>.hand.json) from its URDF or MJCF",
    [](CLI::App& app) {
      auto args = std::make_shared<HandInitArgs>();
      CLI::App* cmd = app.add_subcommand(
          "hand-init",
          "Draft a hand sidecar (<stem>.hand.json) from the URDF alone: palm link, palm frame and "
          "approach axis from where the fingers close, closing joints and directions, fingers as "
          "chains, preshape; prints each guess and why, and names any field it could not decide "
          "(exit status 1)");
      cmd->add_option("urdf", args->urdf, "hand URDF or MJCF")->required();
      cmd->add_option("-o,--output", args->output,
                      "write the sidecar here (default: print it), e.g. HAND.hand.json");
      cmd->add_flag("--force", args->force, "replace an existing -o file");
      addPackagePathOption(cmd);
      cmd->callback([args]() { run(*args); });
    });

}  // namespace
}  // namespace taskmap::cli
