// An ACRONYM grasp file as a task map file, in a child process with limits (acronym_import.hpp).
#include "taskmap/builder/acronym_import.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <nlohmann/json.hpp>

#include "taskmap/builder/map_builder.hpp"
#include "taskmap/core/bounded_child.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/grasp_sim/jaw_closing.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

// The child's work: read, load, convert, close the jaws, write; the result as one line of text
// for the parent.
std::string importInChild(const AcronymFileImportOptions& options) {
  const AcronymGrasps grasps = readAcronym(options.acronym);
  if (!std::filesystem::exists(options.object)) {
    throw Error("object mesh '" + options.object + "' does not exist; give the mesh that " +
                options.acronym + " refers to (object/file: '" + grasps.object_file + "')");
  }
  MeshLoadOptions load;
  load.scale = options.scale > 0 ? options.scale : grasps.object_scale;
  const ObjectModel model = ObjectModel::load(options.object, load);
  AcronymImportOptions poses_only = options.import;
  poses_only.cluster = options.import.cluster && options.hand.empty();
  TaskMapData map = acronymToMap(grasps, mapObjectOf(model), poses_only);
  ImportedJaws jaws;
  if (!options.hand.empty()) {
    // Absolute: validation finds the hand from any working directory (recorded_hand.hpp).
    const std::string urdf = std::filesystem::absolute(resolveHandUrdf(options.hand)).string();
    std::vector<std::size_t> source;
    for (std::size_t i = 0; i < grasps.success.size(); ++i)
      if (!options.import.successful_only || grasps.success[i] != 0) source.push_back(i);
    std::optional<ClusteringOptions> clustering;
    if (options.import.cluster) clustering = options.import.clustering;
    jaws = closeImportedJaws(&map, HandModel::load(urdf), urdf, model, source, clustering);
  }
  if (options.timestamp) map.created_utc = mapCreationTime(true);
  writeMap(options.output, map);
  std::size_t successes = 0;
  for (auto fc : map.grasps.force_closure) successes += fc;
  char line[200];
  std::snprintf(line, sizeof line, "%zu %zu %lld %.17g %d %zu %zu ", map.grasps.size(), successes,
                map.clustering ? static_cast<long long>(map.clustering->clusters.size()) : -1LL,
                load.scale, options.hand.empty() ? 0 : 1, jaws.missed.size(), jaws.overlaps.size());
  return line + model.name();
}

/// Keeps rows `keep` of grasps without contacts (an imported map's), with joint values `joints`
/// (one row per kept grasp).
MapGrasps keepRows(const MapGrasps& in, const std::vector<std::size_t>& keep,
                   const RowMatrixXd& joints) {
  MapGrasps out = in;
  const auto n = static_cast<Eigen::Index>(keep.size());
  out.pose.resize(n, 7);
  out.force_closure.clear();
  out.epsilon.clear();
  out.volume.clear();
  for (Eigen::Index k = 0; k < n; ++k) {
    const std::size_t i = keep[static_cast<std::size_t>(k)];
    out.pose.row(k) = in.pose.row(static_cast<Eigen::Index>(i));
    out.force_closure.push_back(in.force_closure[i]);
    out.epsilon.push_back(in.epsilon[i]);
    out.volume.push_back(in.volume[i]);
  }
  out.joints = joints;
  out.contact_offsets.assign(keep.size() + 1, 0);
  return out;
}

/// Moves each dropped grasp's sampling outcome from force_closure / not_force_closure to
/// `outcome`.
void recount(TaskMapData* map, const std::vector<std::size_t>& dropped, const char* outcome) {
  for (std::size_t i : dropped) {
    auto& from =
        map->sampling
            .outcomes[map->grasps.force_closure[i] ? "force_closure" : "not_force_closure"];
    --from;
    ++map->sampling.outcomes[outcome];
  }
}

}  // namespace

ImportedJaws closeImportedJaws(TaskMapData* map, const HandModel& hand,
                               const std::string& hand_path, const ObjectModel& object,
                               const std::vector<std::size_t>& source,
                               const std::optional<ClusteringOptions>& clustering) {
  const std::size_t n = map->grasps.size();
  if (source.size() != n)
    throw Error("closing imported jaws: " + std::to_string(source.size()) + " source indices for " +
                std::to_string(n) + " grasps");
  const JawCloser closer(hand, object);
  ImportedJaws r;
  std::vector<std::size_t> keep, missed;  // grasp indices
  RowMatrixXd joints(static_cast<Eigen::Index>(n), hand.preshape().size());
  for (std::size_t i = 0; i < n; ++i) {
    const JawClosing c = closer.close(map->grasps.poseAt(i));
    if (c.status == JawClosingStatus::kMissed) {
      missed.push_back(i);
      r.missed.push_back(source[i]);
      continue;
    }
    if (c.status == JawClosingStatus::kOverlaps) r.overlaps.push_back(source[i]);
    joints.row(static_cast<Eigen::Index>(keep.size())) = c.joints.transpose();
    keep.push_back(i);
  }
  if (keep.empty())
    throw Error("closing imported jaws: the jaws of hand '" + hand.name() + "' miss the object " +
                "at every one of the " + std::to_string(n) +
                " poses (is the hand's root link the gripper base frame of the file?)");
  r.closed = keep.size();
  recount(map, missed, "jaws_missed");
  for (auto it = map->sampling.outcomes.begin(); it != map->sampling.outcomes.end();)
    it = it->second == 0 ? map->sampling.outcomes.erase(it) : std::next(it);
  map->grasps = keepRows(map->grasps, keep, joints.topRows(static_cast<Eigen::Index>(keep.size())));
  map->validation.reset();
  map->clustering.reset();
  if (clustering && keep.size() >= 2) {
    std::vector<Pose> poses;
    for (std::size_t i = 0; i < keep.size(); ++i) poses.push_back(map->grasps.poseAt(i));
    ClusteringOptions co = *clustering;
    co.rotation_scale = map->grasps.rotation_scale;
    map->clustering = clusterGrasps(poses, map->grasps.epsilon, co);
  }
  map->hand.name = hand.name();
  map->hand.urdf_sha256 = hand.urdfSha256();
  map->hand.joint_names = hand.jointNames();
  map->hand.link_names.clear();
  for (const HandLink& l : hand.links()) map->hand.link_names.push_back(l.name);
  auto params = nlohmann::json::parse(map->sampling.params_json, nullptr, false);
  if (!params.is_object()) params = nlohmann::json::object();
  params["hand"] = hand_path;
  params["joints"] =
      "the hand's jaws closed from open at the imported pose until both touch "
      "the object (grasp_sim jaw_closing.hpp)";
  params["hold_closing"] = "from_open";
  params["jaws_missed"] = r.missed;
  params["jaws_overlap"] = r.overlaps;
  map->sampling.params_json = params.dump();
  map->validate();
  return r;
}

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
  int jaws = 0;
  if (!(in >> r.grasps >> r.successes >> clusters >> r.scale >> jaws >> r.jaws_missed >>
        r.jaws_overlap))
    throw Error("internal: unreadable import result '" + text + "'");
  r.jaws_closed = jaws != 0;
  in.get();
  std::getline(in, r.object_name);
  if (clusters >= 0) r.clusters = static_cast<std::size_t>(clusters);
  return r;
}

}  // namespace taskmap
