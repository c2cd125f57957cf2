// taskmap validate: label a map's grasps with the physics hold test (validate stage,
// docs/VALIDATION.md) and write the labels into the map (atomically, re-sealed).
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "command.hpp"
#include "taskmap/builder/resimulate.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/core/stop_signals.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/mapstore/recorded_hand.hpp"
#include "taskmap/validate/hold_test.hpp"
#include "taskmap/validate/validate_map.hpp"

namespace taskmap::cli {
namespace {

struct ValidateArgs {
  std::string map, output, hand;
  ValidateOptions options;
  bool json = false, quiet = false, force = false, full = false;
  std::string integrator = "implicit";  ///< --integrator
  long long trace = -1;                 ///< >= 0: trace this grasp instead of labelling the map
};

nlohmann::ordered_json reportJson(const ValidationSummary& s, const ValidateArgs& a) {
  nlohmann::ordered_json j;
  j["map"] = a.map;
  j["output"] = a.output.empty() ? a.map : a.output;
  j.update(nlohmann::ordered_json::parse(summaryJson(s)));
  return j;
}

HandModel mapHand(const TaskMapData& map, const ValidateArgs& args) {
  try {
    checkMapJoints(map);
  } catch (const Error& e) {
    throw Error("validate: map '" + args.map + "': " + e.what());
  }
  std::string urdf = args.hand;
  if (urdf.empty()) {
    try {
      urdf = findMapHandUrdf(map);
    } catch (const Error& e) {
      throw Error("validate: map '" + args.map + "': " + e.what() + "; pass --hand URDF");
    }
  }
  return HandModel::load(urdf);
}

// --trace: one grasp's hold test with the object's path; the map is not written.
void runTrace(const ValidateArgs& args) {
  if (!args.output.empty()) throw Error("validate: --trace writes nothing; leave out -o");
  const TaskMapData map = readMap(args.map);
  const HandModel hand = mapHand(map, args);
  const HoldTrace t =
      traceGrasp(map, hand, static_cast<std::size_t>(args.trace), args.options.hold);
  if (args.json)
    std::cout << nlohmann::ordered_json::parse(traceJson(t, hand)).dump(2) << "\n";
  else
    std::cout << "taskmap validate: grasp " << args.trace << " of " << args.map << "\n"
              << traceText(t, hand);
}

void runValidate(const ValidateArgs& args) {
  if (args.trace >= 0) return runTrace(args);
  if (!args.output.empty())
    checkOutputPath(args.output, {args.map, args.hand}, OutputKind::kTaskMap, args.force);
  TaskMapData map = readMap(args.map);
  const HandModel hand = mapHand(map, args);
  const bool terminal = ::isatty(STDERR_FILENO) != 0 && !args.quiet;
  ValidateControl control;
  control.progress = [terminal](const ValidateProgress& p) {
    if (!terminal) return;
    std::fprintf(stderr, "\rtaskmap validate: %zu / %zu grasps, %zu hold", p.done, p.total,
                 p.holding);
  };
  control.stop = StopSignals::flag();
  ValidationSummary s;
  {
    const StopSignals signals;  // also while writing: the write is never cut short
    s = validateMap(&map, hand, args.options, control);
    if (terminal) std::fprintf(stderr, "\n");
    if (s.status == ValidationSummary::Status::kCompleted)
      writeMap(args.output.empty() ? args.map : args.output, map);
  }
  if (s.status == ValidationSummary::Status::kInterrupted) {
    std::cerr << "taskmap validate: " << s.message << "\n";
    exitCode() = 130;
    return;
  }
  if (args.json) {
    std::cout << reportJson(s, args).dump(2) << "\n";
  } else if (!args.quiet) {
    std::cout << summaryText(s, args.output.empty() ? args.map : args.output);
  }
}

const CommandRegistrar kRegistrar(
    "validate", "Test in physics whether a map's grasps hold; store the labels in the map",
    [](CLI::App& app) {
      auto a = std::make_shared<ValidateArgs>();
      HoldTestOptions& h = a->options.hold;
      CLI::App* cmd = app.add_subcommand(
          "validate",
          "Test whether a map's grasps hold the object in physics (DexGraspBench's protocol in "
          "MuJoCo: the hand closes on a free 0.1 kg object, then a push of 1 N along each object "
          "axis; docs/VALIDATION.md) and store the labels in the map (/grasps/hold).");
      cmd->add_option("map", a->map, "task map (.h5); labels are written into it unless -o")
          ->required()
          ->check(CLI::ExistingFile);
      cmd->add_option("-o,--output", a->output, "write the labelled map here instead");
      cmd->add_option(
          "--hand", a->hand,
          "hand URDF or MJCF (default: the one the map was built with, found by its SHA-256)");
      cmd->add_option("--threads", a->options.threads, "worker threads (0: all cores)")
          ->check(CLI::Range(0, 1024));
      cmd->add_option("--grasps", a->options.grasps, "test only the first N grasps (0: all)");
      cmd->add_option("--object-mass", h.object_mass, "object mass, kg")->capture_default_str();
      cmd->add_option("--friction", h.sliding_friction, "sliding friction coefficient")
          ->capture_default_str();
      cmd->add_option("--jaw-force", h.jaw_force, "parallel jaws: force of each jaw, N")
          ->capture_default_str();
      cmd->add_option("--kp", h.kp_revolute, "position gain of revolute joints, N m/rad")
          ->capture_default_str();
      cmd->add_option("--max-translation", h.max_translation, "failure displacement, m")
          ->capture_default_str();
      cmd->add_option("--max-penetration", h.max_penetration, "initial penetration limit, m")
          ->capture_default_str();
      cmd->add_flag(
          "--robust", a->options.robust,
          "also the robust label: every grasp again with the palm moved 1 mm and turned 2 "
          "deg along and about each palm axis, friction 0.5 and a second decomposition of "
          "the object, each within a margin of 1 cm and 5 deg (docs/VALIDATION.md, \"The "
          "robust label\")");
      cmd->add_flag(
          "--full", a->full,
          "run every push its whole 2 s, as DexGraspBench publishes the protocol (default: "
          "a push ends once the object has settled; same labels, docs/VALIDATION.md)");
      cmd->add_option("--integrator", a->integrator,
                      "how MuJoCo integrates: implicit (every map's labels so far) or implicitfast "
                      "(DexGraspBench's, about 1.3x faster; docs/VALIDATION.md, \"The "
                      "integrator\")")
          ->check(CLI::IsMember(integratorNames()))
          ->capture_default_str();
      cmd->add_flag("!--protocol-dynamics", h.stated_dynamics,
                    "an MJCF hand: use the protocol's masses, gains, damping and friction, not the "
                    "ones the hand's model states (docs/VALIDATION.md, \"A hand's own dynamics\")");
      cmd->add_option("--trace", a->trace,
                      "test only grasp I (index from 0) and print where the object goes and which "
                      "links press it, stage by stage; writes nothing")
          ->check(CLI::NonNegativeNumber);
      cmd->add_flag("--json", a->json, "print the summary (or the --trace) as JSON");
      cmd->add_flag("--force", a->force, "replace an existing -o file that is not a task map");
      cmd->add_flag("-q,--quiet", a->quiet, "print nothing but errors");
      cmd->callback([a]() {
        a->options.hold.settle_stop = !a->full;
        a->options.hold.integrator = integratorFromName(a->integrator);
        runValidate(*a);
      });
    });

}  // namespace
}  // namespace taskmap::cli
