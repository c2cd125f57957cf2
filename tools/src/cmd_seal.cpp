// taskmap seal: re-seal a task map on purpose (after an edit with h5py or another HDF5 tool,
// or a schema-1 map written before seals). HDF5 parses the unverified file here, so the work
// runs in a child process with CPU-time and memory limits: a file that crashes or hangs HDF5
// is refused instead of taking the tool down.
#include <cstdint>
#include <iostream>
#include <memory>
#include <string>

#include "command.hpp"
#include "taskmap/core/bounded_child.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap::cli {
namespace {

struct SealArgs {
  std::string map;
  int cpu_seconds = 120;
  double memory_gib = 8.0;
  bool quiet = false;
};

void runSeal(const SealArgs& args) {
  const ParseBudget limits{static_cast<std::uint64_t>(args.memory_gib * (1ull << 30)),
                           args.cpu_seconds};
  runBounded(
      [&args] {
        sealMap(args.map);
        return std::string();
      },
      limits, "cannot seal task map '" + args.map + "'");
  if (!args.quiet) std::cout << "taskmap seal: sealed " << args.map << "\n";
}

const CommandRegistrar kRegistrar(
    "seal", "Re-seal a map on purpose after editing it with another HDF5 tool", [](CLI::App& app) {
      auto args = std::make_shared<SealArgs>();
      CLI::App* cmd = app.add_subcommand(
          "seal",
          "Re-seal a task map on purpose. Every reader refuses a map whose content does not match "
          "the SHA-256 in its first 512 bytes (damaged, or edited with h5py or another HDF5 tool) "
          "and maps without a seal (written by other tools or before schema 2). If you trust the "
          "file, this validates it as a task map (in a separate process with CPU and memory "
          "limits) and rewrites it atomically with a fresh seal.");
      cmd->add_option("map", args->map, "task map (.h5), rewritten in place (atomically)")
          ->required()
          ->check(CLI::ExistingFile);
      cmd->add_option("--cpu-seconds", args->cpu_seconds, "CPU-time limit of the validation")
          ->check(CLI::Range(1, 86400));
      cmd->add_option("--memory-gib", args->memory_gib, "address-space limit of the validation")
          ->check(CLI::Range(0.25, 1024.0));
      cmd->add_flag("-q,--quiet", args->quiet, "print nothing");
      cmd->callback([args]() { runSeal(*args); });
    });

}  // namespace
}  // namespace taskmap::cli
