// `--validate` of taskmap build, taskmap-mpi build and dataset: the built map's grasps labelled
// with the physics hold test before the map is written.
#include <cstdio>
#include <iostream>

#include "build_command.hpp"
#include "taskmap/validate/validate_map.hpp"

namespace taskmap::cli {

void validateIfAsked(const BuildArgs& args, const HandModel& hand, TaskMapData* map,
                     const std::string& label) {
  if (!args.validate) return;
  ValidateOptions options;
  options.threads = args.threads;
  const ValidationSummary s = validateMap(map, hand, options);
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
}

}  // namespace taskmap::cli
