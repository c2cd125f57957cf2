// Data sets of task maps: the plan, one job, the manifest, the run.
#include "taskmap/builder/dataset.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <tuple>

#include <nlohmann/json.hpp>

#include "taskmap/builder/build_checkpoint.hpp"
#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/input_file.hpp"
#include "taskmap/core/output_guard.hpp"
#include "taskmap/core/run_lock.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
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
  BuildOptions options = plan.options.build;
  options.seed = seed;
  options.extra_params_json =
      json{{"object", job.object}, {"scale", job.scale}, {"hand", job.hand}}.dump();
  options.validate();
  return options;
}

// What a job's entry starts as.
DatasetEntry baseEntry(const DatasetJob& job) {
  DatasetEntry e;
  e.object = job.object;
  e.scale = job.scale;
  e.hand = job.hand;
  e.file = job.file;
  return e;
}

constexpr DatasetJobStatus kStatuses[] = {DatasetJobStatus::kPending, DatasetJobStatus::kComplete,
                                          DatasetJobStatus::kTrialBudgetExhausted,
                                          DatasetJobStatus::kFailed};

// An entry's JSON object: the fields it has, keys sorted (the manifest's bytes).
json entryJson(const DatasetEntry& e) {
  json j = {{"object", e.object},
            {"scale", e.scale},
            {"hand", e.hand},
            {"file", e.file},
            {"status", toString(e.status)}};
  if (e.seed) j["seed"] = *e.seed;
  if (e.trials) j["trials"] = *e.trials;
  if (e.valid) j["valid"] = *e.valid;
  if (e.file_sha256) j["file_sha256"] = *e.file_sha256;
  if (e.build_sha256) j["build_sha256"] = *e.build_sha256;
  if (e.error) j["error"] = *e.error;
  return j;
}

// The entry of a JSON object (an earlier manifest's, a rank's); throws json::exception.
DatasetEntry entryOf(const json& j) {
  DatasetEntry e;
  e.object = j.at("object").get<std::string>();
  e.scale = j.value("scale", 1.0);
  e.hand = j.at("hand").get<std::string>();
  e.file = j.value("file", "");
  const std::string status = j.value("status", "");
  for (DatasetJobStatus s : kStatuses)
    if (status == toString(s)) e.status = s;
  if (j.contains("seed")) e.seed = j.at("seed").get<std::uint64_t>();
  if (j.contains("trials")) e.trials = j.at("trials").get<std::uint64_t>();
  if (j.contains("valid")) e.valid = j.at("valid").get<std::uint64_t>();
  if (j.contains("file_sha256")) e.file_sha256 = j.at("file_sha256").get<std::string>();
  if (j.contains("build_sha256")) e.build_sha256 = j.at("build_sha256").get<std::string>();
  if (j.contains("error")) e.error = j.at("error").get<std::string>();
  return e;
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

const char* toString(DatasetJobStatus status) {
  switch (status) {
    case DatasetJobStatus::kPending:
      return "pending";
    case DatasetJobStatus::kComplete:
      return "complete";
    case DatasetJobStatus::kTrialBudgetExhausted:
      return "trial_budget_exhausted";
    case DatasetJobStatus::kFailed:
      return "failed";
  }
  return "pending";
}

std::string datasetEntryJson(const DatasetEntry& entry) {
  return entryJson(entry).dump();
}

DatasetEntry datasetEntryFromJson(const std::string& text) {
  try {
    return entryOf(json::parse(text));
  } catch (const json::exception& e) {
    throw Error(std::string("not a data-set entry: ") + e.what());
  }
}

DatasetPlan planDataset(const DatasetOptions& args) {
  DatasetPlan plan;
  plan.options = args;
  if (!(args.scale > 0.0)) throw Error("--scale must be positive");
  args.build.validate();
  plan.dir = args.output;
  std::error_code ec;
  fs::create_directories(plan.dir, ec);
  if (!fs::is_directory(plan.dir))
    throw Error("cannot create output directory '" + plan.dir + "'" +
                (ec ? " (" + ec.message() + ")" : ""));
  checkManifestPath((fs::path(plan.dir) / "manifest.json").string(), args.force);
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
                      OutputKind::kTaskMap, args.force);
      plan.jobs.push_back(std::move(job));
    }
  }
  std::sort(plan.jobs.begin(), plan.jobs.end(), [](const DatasetJob& a, const DatasetJob& b) {
    if (a.mesh_bytes != b.mesh_bytes) return a.mesh_bytes > b.mesh_bytes;
    return std::tie(a.object, a.hand) < std::tie(b.object, b.hand);
  });
  return plan;
}

DatasetEntry runDatasetJob(const DatasetPlan& plan, const DatasetJob& job,
                           const BuildControl& control) {
  DatasetEntry entry = baseEntry(job);
  entry.status = DatasetJobStatus::kFailed;
  try {
    const ObjectModel object = ObjectModel::load(job.object_path, MeshLoadOptions{job.scale});
    const HandModel hand = HandModel::load(job.hand_urdf);
    const std::uint64_t seed =
        jobSeed(plan.options.build.seed, object.sourceSha256(), hand.urdfSha256());
    entry.seed = seed;
    const BuildOptions options = jobOptions(plan, job, seed);
    BuildResult result = buildMap(object, hand, options, control);
    if (result.status == BuildStatus::kInterrupted) return baseEntry(job);  // still pending
    if (result.status == BuildStatus::kNoGrasps) throw Error(result.message);
    if (plan.options.timestamp) result.map.created_utc = mapCreationTime(true);
    entry.validation =
        labelHolds(plan.options.validation, options, hand, control.stop, &result.map);
    if (control.stopRequested()) return baseEntry(job);  // stopped in the validation: pending
    const std::string path = (fs::path(plan.dir) / job.file).string();
    writeMap(path, result.map);
    entry.status = result.status == BuildStatus::kComplete
                       ? DatasetJobStatus::kComplete
                       : DatasetJobStatus::kTrialBudgetExhausted;
    entry.trials = result.map.sampling.trials;
    entry.valid = static_cast<std::uint64_t>(std::count(result.map.grasps.force_closure.begin(),
                                                        result.map.grasps.force_closure.end(), 1));
    entry.file_sha256 = sha256File(path);
    entry.build_sha256 = sha256Hex(buildIdentity(object, hand, options, 0));
    entry.error = "";
  } catch (const std::exception& e) {
    entry.error = e.what();
  }
  return entry;
}

DatasetManifest::DatasetManifest(const DatasetPlan& plan) : plan_(plan) {
  const std::string path = (fs::path(plan.dir) / "manifest.json").string();
  std::map<std::pair<std::string, std::string>, DatasetEntry> earlier;
  std::error_code ec;
  if (fs::exists(path, ec)) {
    try {
      if (fs::file_size(path) > kMaxManifestBytes) throw Error("larger than 256 MiB");
      std::ifstream in(path);
      const json m = json::parse(in);
      if (m.value("format", "") != kManifestFormat) throw Error("not a taskmap data-set manifest");
      for (const json& e : m.at("jobs"))
        earlier[{e.at("object").get<std::string>(), e.at("hand").get<std::string>()}] = entryOf(e);
    } catch (const std::exception& e) {
      note_ = "ignoring manifest '" + path + "': " + e.what();
      earlier.clear();
    }
  }
  for (const DatasetJob& job : plan.jobs) {
    const auto it = earlier.find({job.object, job.hand});
    entries_.push_back(it != earlier.end() ? it->second : baseEntry(job));
  }
}

bool DatasetManifest::finishedEarlier(std::size_t i) const {
  const DatasetEntry& e = entries_[i];
  if (e.status != DatasetJobStatus::kComplete &&
      e.status != DatasetJobStatus::kTrialBudgetExhausted)
    return false;
  const DatasetJob& job = plan_.jobs[i];
  try {
    const std::string path = (fs::path(plan_.dir) / job.file).string();
    if (e.file != job.file || !fs::exists(path)) return false;
    const ObjectModel object = ObjectModel::load(job.object_path, MeshLoadOptions{job.scale});
    const HandModel hand = HandModel::load(job.hand_urdf);
    const std::uint64_t seed =
        jobSeed(plan_.options.build.seed, object.sourceSha256(), hand.urdfSha256());
    const BuildOptions options = jobOptions(plan_, job, seed);
    return e.build_sha256.value_or("") == sha256Hex(buildIdentity(object, hand, options, 0)) &&
           e.file_sha256.value_or("") == sha256File(path);
  } catch (const std::exception&) {
    return false;
  }
}

void DatasetManifest::set(std::size_t i, DatasetEntry entry) {
  entries_[i] = std::move(entry);
}

std::vector<std::size_t> DatasetManifest::startRun() {
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < plan_.jobs.size(); ++i) {
    if (finishedEarlier(i)) continue;
    todo.push_back(i);
    entries_[i] = baseEntry(plan_.jobs[i]);
  }
  write();
  return todo;
}

std::string datasetLockPath(const DatasetPlan& plan) {
  return (fs::path(plan.dir) / ".taskmap-dataset.lock").string();
}

void DatasetManifest::write() const {
  std::vector<const DatasetEntry*> sorted;
  for (const DatasetEntry& e : entries_) sorted.push_back(&e);
  std::sort(sorted.begin(), sorted.end(), [](const DatasetEntry* a, const DatasetEntry* b) {
    return std::tie(a->object, a->hand) < std::tie(b->object, b->hand);
  });
  json jobs = json::array();
  for (const DatasetEntry* e : sorted) jobs.push_back(entryJson(*e));
  const BuildOptions& build = plan_.options.build;
  const json m = {{"format", kManifestFormat},
                  {"seed", build.seed},
                  {"valid", build.valid_target},
                  {"trials", build.max_trials},
                  {"jobs", jobs}};
  const std::string path = (fs::path(plan_.dir) / "manifest.json").string();
  writeFileAtomically(path, m.dump(2) + "\n", "cannot write manifest '" + path + "'");
}

std::size_t DatasetManifest::failed() const {
  return static_cast<std::size_t>(
      std::count_if(entries_.begin(), entries_.end(),
                    [](const DatasetEntry& e) { return e.status == DatasetJobStatus::kFailed; }));
}

struct DatasetRun::Impl {
  explicit Impl(const DatasetOptions& options)
      : plan(planDataset(options)),
        lock(datasetLockPath(plan), "data set directory '" + plan.dir + "'"),
        manifest(plan) {}
  DatasetPlan plan;
  RunLock lock;
  DatasetManifest manifest;
};

DatasetRun::DatasetRun(const DatasetOptions& options) : impl_(std::make_unique<Impl>(options)) {}

DatasetRun::~DatasetRun() = default;

const DatasetPlan& DatasetRun::plan() const {
  return impl_->plan;
}

const std::string& DatasetRun::note() const {
  return impl_->manifest.note();
}

DatasetResult DatasetRun::run(const RunControl<DatasetProgress>& control,
                              const BuildControl& build_control) {
  const DatasetPlan& plan = impl_->plan;
  DatasetManifest& manifest = impl_->manifest;
  const std::vector<std::size_t> todo = manifest.startRun();  // largest first
  DatasetResult result;
  result.jobs = plan.jobs.size();
  result.skipped = plan.jobs.size() - todo.size();
  result.dir = plan.dir;
  BuildControl build = build_control;
  build.stop = control.stop;
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < todo.size() && !control.stopRequested(); ++k) {
    DatasetEntry entry = runDatasetJob(plan, plan.jobs[todo[k]], build);
    if (control.stopRequested() && entry.status == DatasetJobStatus::kPending) break;
    manifest.set(todo[k], entry);
    manifest.write();
    if (!control.progress) continue;
    DatasetProgress p;
    p.done = k + 1;
    p.total = todo.size();
    p.elapsed_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    p.entry = std::move(entry);
    control.progress(p);
  }
  manifest.write();
  result.failed = manifest.failed();
  result.interrupted = control.stopRequested();
  return result;
}

}  // namespace taskmap
