// `--validate` of taskmap build, taskmap-mpi build and dataset: the built map's grasps labelled
// with the physics hold test before the map is written.
#include <cstdio>
#include <iostream>
#include <string>

#include "taskmap/core/error.hpp"

#include "build_command.hpp"
#include "taskmap/validate/validate_map.hpp"

namespace taskmap::cli {

void validateIfAsked(const BuildArgs& args, const HandModel& hand, TaskMapData* map,
                     const std::string& label) {
  if (!args.validate) return;
  ValidateOptions options;
  options.threads = args.threads;
  const ValidationSummary s = validateMap(map, hand, options);
  const std::size_t before = map->grasps.size();
  const std::size_t kept =
      args.keep_holding ? keepHoldingGrasps(map, knobOptions(args).clustering) : before;
  if (kept == 0)
    throw Error(label + ": --keep-holding: none of the " + std::to_string(before) +
                " grasps holds in the physics test; nothing written");
  if (args.quiet) return;
  char line[200];
  std::snprintf(
      line, sizeof line,
      "%s: physics validation: %zu of %zu grasps hold (%.1f %%), %.1f grasps per "
      "CPU-second\n",
      label.c_str(), s.holding, s.tested,
      s.tested ? 100.0 * static_cast<double>(s.holding) / static_cast<double>(s.tested) : 0.0,
      s.cpu_seconds > 0 ? static_cast<double>(s.tested) / s.cpu_seconds : 0.0);
  std::cerr << line;
  if (args.keep_holding)
    std::cerr << label << ": --keep-holding: kept " << kept << " of " << before
              << " grasps (the others do not hold)\n";
}

}  // namespace taskmap::cli
