// Data sets of task maps: the plan, one job, the manifest.
#include "dataset.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "output_guard.hpp"
#include "taskmap/builder/build_checkpoint.hpp"
#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/input_file.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kManifestFormat = "taskmap-dataset 1";
constexpr std::uintmax_t kMaxManifestBytes = std::uintmax_t{256} << 20;

/// One line of the object list: the mesh as written, resolved, and its scale (0: --scale's).
struct ListedObject {
  std::string entry, path;
  double scale = 0.0;
};

// The meshes of the list file, as written and resolved, each with its scale when the line
// gives one after the path ("meshes/bunny.ply 0.01").
std::vector<ListedObject> readObjectList(const std::string& list) {
  std::error_code ec;
  if (fs::exists(list, ec)) requireRegularFile(list, "object list");  // a FIFO blocks ifstream
  std::ifstream in(list);
  if (!in) throw Error("cannot read object list '" + list + "'");
  const fs::path base = fs::absolute(list).parent_path();
  std::vector<ListedObject> objects;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const auto begin = line.find_first_not_of(" \t\r");
    if (begin == std::string::npos || line[begin] == '#') continue;
    const auto end = line.find_last_not_of(" \t\r");
    std::string entry = line.substr(begin, end - begin + 1);
    double scale = 0.0;
    const auto gap = entry.find_last_of(" \t");
    if (gap != std::string::npos) {
      const std::string last = entry.substr(gap + 1);
      char* stop = nullptr;
      const double value = std::strtod(last.c_str(), &stop);
      const bool number_token = !last.empty() && stop == last.c_str() + last.size();
      if (number_token) {
        if (!(value > 0.0) || !std::isfinite(value))
          throw Error("object list '" + list + "' line " + std::to_string(number) + ": scale '" +
                      last + "' must be a positive number (file units to metres)");
        scale = value;
        entry = entry.substr(0, entry.find_last_not_of(" \t", gap) + 1);
      }
    }
    const fs::path p(entry);
    objects.push_back({entry, (p.is_absolute() ? p : base / p).lexically_normal().string(), scale});
  }
  if (objects.empty())
    throw Error("object list '" + list +
                "' names no mesh (one path a line, optionally followed "
                "by its scale)");
  return objects;
}

std::vector<std::string> splitHands(const std::string& hands) {
  std::vector<std::string> out;
  std::stringstream ss(hands);
  for (std::string h; std::getline(ss, h, ',');)
    if (!h.empty()) out.push_back(h);
  if (out.empty()) throw Error("--hands names no hand (comma-separated URDFs or bundled names)");
  return out;
}

// Job seed from the data set's seed and the contents of mesh and hand.
std::uint64_t jobSeed(std::uint64_t seed, const std::string& mesh_sha,
                      const std::string& urdf_sha) {
  const std::string h = sha256Hex("taskmap dataset seed\n" + std::to_string(seed) + "\n" +
                                  mesh_sha + "\n" + urdf_sha + "\n");
  return std::stoull(h.substr(0, 16), nullptr, 16);
}

// The build of one job: knobs, derived seed, the paths recorded in params_json.
BuildOptions jobOptions(const DatasetPlan& plan, const DatasetJob& job, std::uint64_t seed) {
  BuildOptions options = knobOptions(plan.args.knobs);
  options.seed = seed;
  options.extra_params_json =
      json{{"object", job.object}, {"scale", job.scale}, {"hand", job.hand}}.dump();
  options.validate();
  return options;
}

// What a job's entry starts as.
json baseEntry(const DatasetJob& job) {
  return json{{"object", job.object}, {"scale", job.scale}, {"hand", job.hand}, {"file", job.file}};
}

// An existing manifest.json that is not a taskmap data-set manifest (a user's file) is not
// replaced without --force; a damaged manifest of ours is (the note says so).
void checkManifestPath(const std::string& path, bool force) {
  std::error_code ec;
  if (!fs::exists(path, ec)) return;
  if (!fs::is_regular_file(path, ec))
    throw Error("'" + path + "' exists and is not a regular file; choose another directory");
  if (force || fs::file_size(path, ec) == 0) return;
  std::ifstream in(path, std::ios::binary);
  std::string headBytes(4096, '\0');
  in.read(headBytes.data(), static_cast<std::streamsize>(headBytes.size()));
  headBytes.resize(static_cast<std::size_t>(in.gcount()));
  if (headBytes.find(kManifestFormat) == std::string::npos)
    throw Error("'" + path +
                "' exists and is not a taskmap data-set manifest; refusing to "
                "replace it (add --force to overwrite it)");
}

}  // namespace

void addDatasetOptions(CLI::App& cmd, DatasetArgs& args) {
  cmd.add_option("--objects", args.objects,
                 "text file naming one mesh a line (relative to the file; # comments), "
                 "optionally followed by its scale (file units to metres), e.g. "
                 "\"bunny.ply 0.01\"; without one a mesh takes --scale")
      ->required();
  cmd.add_option("--hands", args.hands, "comma-separated hand URDFs or bundled hand names")
      ->required();
  cmd.add_option("-o,--output", args.output, "directory for the maps and manifest.json")
      ->required();
  cmd.add_option("--scale", args.scale,
                 "multiplies the coordinates of every mesh the list gives no scale (file units "
                 "-> m)")
      ->capture_default_str();
  addBuildKnobs(cmd, args.knobs);
  cmd.add_flag("--force", args.knobs.force,
               "replace existing map files (and manifest.json) in the directory that are not "
               "taskmap files (never an input)");
}

DatasetPlan planDataset(const DatasetArgs& args) {
  DatasetPlan plan;
  plan.args = args;
  if (!(args.scale > 0.0)) throw Error("--scale must be positive");
  knobOptions(args.knobs).validate();
  plan.dir = args.output;
  std::error_code ec;
  fs::create_directories(plan.dir, ec);
  if (!fs::is_directory(plan.dir))
    throw Error("cannot create output directory '" + plan.dir + "'" +
                (ec ? " (" + ec.message() + ")" : ""));
  checkManifestPath((fs::path(plan.dir) / "manifest.json").string(), args.knobs.force);
  std::map<std::string, std::string> writers;  // file -> object, hand
  for (const ListedObject& listed : readObjectList(args.objects)) {
    const std::string& object = listed.entry;
    const std::string& path = listed.path;
    for (const std::string& hand : splitHands(args.hands)) {
      DatasetJob job{object,
                     path,
                     hand,
                     resolveHandUrdf(hand),
                     "",
                     0,
                     listed.scale > 0.0 ? listed.scale : args.scale};
      job.file =
          fs::path(path).stem().string() + "__" + fs::path(job.hand_urdf).stem().string() + ".h5";
      const auto [it, fresh] = writers.emplace(job.file, object + " with " + hand);
      if (!fresh)
        throw Error("'" + object + "' with " + hand + " and " + it->second + " would both write " +
                    job.file + "; rename one mesh");
      job.mesh_bytes = fs::is_regular_file(path, ec) ? fs::file_size(path, ec) : 0;
      checkOutputPath((fs::path(plan.dir) / job.file).string(),
                      {path, job.hand_urdf, handSidecarPath(job.hand_urdf), args.objects},
                      OutputKind::kTaskMap, args.knobs.force);
      plan.jobs.push_back(std::move(job));
    }
  }
  std::sort(plan.jobs.begin(), plan.jobs.end(), [](const DatasetJob& a, const DatasetJob& b) {
    if (a.mesh_bytes != b.mesh_bytes) return a.mesh_bytes > b.mesh_bytes;
    return std::tie(a.object, a.hand) < std::tie(b.object, b.hand);
  });
  return plan;
}

json runDatasetJob(const DatasetPlan& plan, const DatasetJob& job) {
  json entry = baseEntry(job);
  entry["status"] = "failed";
  try {
    const ObjectModel object = ObjectModel::load(job.object_path, MeshLoadOptions{job.scale});
    const HandModel hand = HandModel::load(job.hand_urdf);
    const std::uint64_t seed =
        jobSeed(plan.args.knobs.seed, object.sourceSha256(), hand.urdfSha256());
    entry["seed"] = seed;
    const BuildOptions options = jobOptions(plan, job, seed);
    BuildResult result = buildMap(object, hand, options);
    if (result.status == BuildStatus::kNoGrasps) throw Error(result.message);
    if (plan.args.knobs.timestamp) result.map.created_utc = mapCreationTime(true);
    validateIfAsked(plan.args.knobs, hand, &result.map, "taskmap dataset");
    const std::string path = (fs::path(plan.dir) / job.file).string();
    writeMap(path, result.map);
    entry["status"] = toString(result.status);
    entry["trials"] = result.map.sampling.trials;
    entry["valid"] = std::count(result.map.grasps.force_closure.begin(),
                                result.map.grasps.force_closure.end(), 1);
    entry["file_sha256"] = sha256File(path);
    entry["build_sha256"] = sha256Hex(buildIdentity(object, hand, options, 0));
    entry["error"] = "";
  } catch (const std::exception& e) {
    entry["error"] = e.what();
  }
  return entry;
}

DatasetManifest::DatasetManifest(const DatasetPlan& plan) : plan_(plan) {
  const std::string path = (fs::path(plan.dir) / "manifest.json").string();
  std::map<std::pair<std::string, std::string>, json> earlier;
  std::error_code ec;
  if (fs::exists(path, ec)) {
    try {
      if (fs::file_size(path) > kMaxManifestBytes) throw Error("larger than 256 MiB");
      std::ifstream in(path);
      const json m = json::parse(in);
      if (m.value("format", "") != kManifestFormat) throw Error("not a taskmap data-set manifest");
      for (const json& e : m.at("jobs"))
        earlier[{e.at("object").get<std::string>(), e.at("hand").get<std::string>()}] = e;
    } catch (const std::exception& e) {
      note_ = "ignoring manifest '" + path + "': " + e.what();
      earlier.clear();
    }
  }
  for (const DatasetJob& job : plan.jobs) {
    const auto it = earlier.find({job.object, job.hand});
    if (it != earlier.end()) {
      entries_.push_back(it->second);
    } else {
      json e = baseEntry(job);
      e["status"] = "pending";
      entries_.push_back(e);
    }
  }
}

bool DatasetManifest::finishedEarlier(std::size_t i) const {
  const json& e = entries_[i];
  const std::string status = e.value("status", "");
  if (status != "complete" && status != "trial_budget_exhausted") return false;
  const DatasetJob& job = plan_.jobs[i];
  try {
    const std::string path = (fs::path(plan_.dir) / job.file).string();
    if (e.value("file", "") != job.file || !fs::exists(path)) return false;
    const ObjectModel object = ObjectModel::load(job.object_path, MeshLoadOptions{job.scale});
    const HandModel hand = HandModel::load(job.hand_urdf);
    const std::uint64_t seed =
        jobSeed(plan_.args.knobs.seed, object.sourceSha256(), hand.urdfSha256());
    const BuildOptions options = jobOptions(plan_, job, seed);
    return e.value("build_sha256", "") == sha256Hex(buildIdentity(object, hand, options, 0)) &&
           e.value("file_sha256", "") == sha256File(path);
  } catch (const std::exception&) {
    return false;
  }
}

void DatasetManifest::set(std::size_t i, json entry) {
  entries_[i] = std::move(entry);
}

std::vector<std::size_t> DatasetManifest::startRun() {
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < plan_.jobs.size(); ++i) {
    if (finishedEarlier(i)) continue;
    todo.push_back(i);
    json e = baseEntry(plan_.jobs[i]);
    e["status"] = "pending";
    entries_[i] = std::move(e);
  }
  write();
  return todo;
}

std::string datasetLockPath(const DatasetPlan& plan) {
  return (fs::path(plan.dir) / ".taskmap-dataset.lock").string();
}

void DatasetManifest::write() const {
  std::vector<const json*> sorted;
  for (const json& e : entries_) sorted.push_back(&e);
  std::sort(sorted.begin(), sorted.end(), [](const json* a, const json* b) {
    return std::make_pair(a->at("object").get<std::string>(), a->at("hand").get<std::string>()) <
           std::make_pair(b->at("object").get<std::string>(), b->at("hand").get<std::string>());
  });
  json jobs = json::array();
  for (const json* e : sorted) jobs.push_back(*e);
  const json m = {{"format", kManifestFormat},
                  {"seed", plan_.args.knobs.seed},
                  {"valid", plan_.args.knobs.valid},
                  {"trials", plan_.args.knobs.trials},
                  {"jobs", jobs}};
  const std::string path = (fs::path(plan_.dir) / "manifest.json").string();
  writeFileAtomically(path, m.dump(2) + "\n", "cannot write manifest '" + path + "'");
}

std::size_t DatasetManifest::failed() const {
  return static_cast<std::size_t>(
      std::count_if(entries_.begin(), entries_.end(),
                    [](const json& e) { return e.value("status", "") == "failed"; }));
}

std::string datasetProgressLine(std::size_t done, std::size_t total, double elapsed_seconds,
                                const json& e) {
  const double eta =
      done > 0 ? elapsed_seconds / static_cast<double>(done) * static_cast<double>(total - done)
               : -1.0;
  std::string line = "[" + std::to_string(done) + "/" + std::to_string(total) + ", ETA " +
                     clockString(eta) + "] " + e.value("object", "?") + " x " +
                     e.value("hand", "?") + ": " + e.value("status", "?");
  if (e.value("status", "") == "failed") return line + ": " + e.value("error", "");
  return line + ", " + std::to_string(e.value("valid", 0)) + " valid in " +
         std::to_string(e.value("trials", 0)) + " trials -> " + e.value("file", "");
}

}  // namespace taskmap::cli
