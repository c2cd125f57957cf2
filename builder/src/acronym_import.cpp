// An ACRONYM grasp file as a task map file, in a child process with limits (acronym_import.hpp).
#include "taskmap/builder/acronym_import.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "taskmap/builder/map_builder.hpp"
#include "taskmap/core/bounded_child.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/meshes/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {
namespace {

// The child's work: read, load, convert, write; the result as one line of text for the parent.
std::string importInChild(const AcronymFileImportOptions& options) {
  const AcronymGrasps grasps = readAcronym(options.acronym);
  if (!std::filesystem::exists(options.object)) {
    throw Error("object mesh '" + options.object + "' does not exist; give the mesh that " +
                options.acronym + " refers to (object/file: '" + grasps.object_file + "')");
  }
  MeshLoadOptions load;
  load.scale = options.scale > 0 ? options.scale : grasps.object_scale;
  const ObjectModel model = ObjectModel::load(options.object, load);
  TaskMapData map = acronymToMap(grasps, mapObjectOf(model), options.import);
  if (options.timestamp) map.created_utc = mapCreationTime(true);
  writeMap(options.output, map);
  std::size_t successes = 0;
  for (auto fc : map.grasps.force_closure) successes += fc;
  char line[128];
  std::snprintf(line, sizeof line, "%zu %zu %lld %.17g ", map.grasps.size(), successes,
                map.clustering ? static_cast<long long>(map.clustering->clusters.size()) : -1LL,
                load.scale);
  return line + model.name();
}

}  // namespace

Eigen::Isometry3d acronymBaseToPalm(const std::optional<double>& palm_offset,
                                    const std::string& hand) {
  if (palm_offset && !hand.empty())
    throw Error("--palm-offset and --hand both set the palm frame: give one");
  if (!hand.empty()) return HandModel::load(resolveHandUrdf(hand)).rootToPalm();
  Eigen::Isometry3d t = acronymFrankaBaseToPalm();
  if (palm_offset) {
    if (!std::isfinite(*palm_offset)) throw Error("--palm-offset must be a finite length");
    t.translation() = Eigen::Vector3d(0, 0, *palm_offset);
  }
  return t;
}

void AcronymFileImportOptions::validate() const {
  if (!(scale >= 0)) throw Error("--scale must be positive");
  if (cpu_seconds < 1 || cpu_seconds > 86400)
    throw Error("--cpu-seconds must be in [1, 86400], not " + std::to_string(cpu_seconds));
  if (!(memory_gib >= 0.25 && memory_gib <= 1024.0))
    throw Error("--memory-gib must be in [0.25, 1024], not " + std::to_string(memory_gib));
  import.validate();
}

AcronymFileImport importAcronymFile(const AcronymFileImportOptions& options) {
  options.validate();
  const ParseBudget budget{
      static_cast<std::uint64_t>(options.memory_gib * 1024.0 * 1024.0 * 1024.0),
      options.cpu_seconds};
  const std::string text = runBounded([&options] { return importInChild(options); }, budget,
                                      "cannot import ACRONYM file '" + options.acronym + "'");
  std::istringstream in(text);
  AcronymFileImport r;
  long long clusters = -1;
  if (!(in >> r.grasps >> r.successes >> clusters >> r.scale))
    throw Error("internal: unreadable import result '" + text + "'");
  in.get();
  std::getline(in, r.object_name);
  if (clusters >= 0) r.clusters = static_cast<std::size_t>(clusters);
  return r;
}

}  // namespace taskmap
