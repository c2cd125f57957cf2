// Task map files: sealed HDF5, schema version 2 (mapstore/SCHEMA.md).
#include "taskmap/mapstore/map_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <limits>

#include "hdf5_io.hpp"
#include "map_seal.hpp"
#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/bounded_child.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

using h5::Id;

constexpr const char* kFormat = "taskmap";
constexpr const char* kOutcomePrefix = "outcome_";

/// The stored linkage name, parsed with clustering's own parser; errors name the attribute.
Linkage linkageByName(const std::string& name) {
  try {
    return linkageFromString(name);
  } catch (const Error& e) {
    throw Error(std::string("/clustering attribute method: ") + e.what());
  }
}

RowMatrixXd toRows(const h5::Array<double>& a, std::size_t cols) {
  RowMatrixXd m(static_cast<Eigen::Index>(a.rows()), static_cast<Eigen::Index>(cols));
  std::copy(a.values.begin(), a.values.end(), m.data());
  return m;
}

// ---------------------------------------------------------------- writing

void writeObject(hid_t file, const MapObject& o) {
  Id g = h5::createGroup(file, "object");
  h5::writeAttr(g, "name", o.name);
  h5::writeAttr(g, "source_sha256", o.source_sha256);
  h5::writeAttr(g, "scale", o.scale);
  h5::writeAttr(g, "volume", o.volume);
  h5::writeAttrVector(g, "center_of_mass", o.center_of_mass.data(), 3);
  h5::writeAttr(g, "torque_scale", o.torque_scale);
  h5::writeDataset(g, "vertices", h5::Type::kF64, o.vertices.data(),
                   static_cast<std::size_t>(o.vertices.rows()), 3);
  h5::writeDataset(g, "faces", h5::Type::kI64, o.faces.data(),
                   static_cast<std::size_t>(o.faces.rows()), 3);
}

void writeHand(hid_t file, const MapHand& h) {
  Id g = h5::createGroup(file, "hand");
  h5::writeAttr(g, "name", h.name);
  h5::writeAttr(g, "urdf_sha256", h.urdf_sha256);
  h5::writeStrings(g, "joint_names", h.joint_names);
  if (!h.link_names.empty()) h5::writeStrings(g, "link_names", h.link_names);
}

void writeSampling(hid_t file, const MapSampling& s) {
  Id g = h5::createGroup(file, "sampling");
  h5::writeAttr(g, "sampler", s.sampler);
  h5::writeAttrUInt(g, "seed", s.seed);
  h5::writeAttrUInt(g, "trials", s.trials);
  h5::writeAttr(g, "params_json", s.params_json);
  for (const auto& [name, count] : s.outcomes) h5::writeAttrUInt(g, kOutcomePrefix + name, count);
}

void writeQuality(hid_t file, const MapQuality& q) {
  Id g = h5::createGroup(file, "quality");
  h5::writeAttr(g, "friction", q.friction);
  h5::writeAttrInt(g, "cone_edges", q.cone_edges);
  h5::writeAttr(g, "contact_model", q.contact_model);
}

void writeGrasps(hid_t file, const TaskMapData& map) {
  const MapGrasps& gr = map.grasps;
  const std::size_t n = gr.size();
  const auto m = static_cast<std::size_t>(gr.contact_points.rows());
  Id g = h5::createGroup(file, "grasps");
  h5::writeAttr(g, "rotation_scale", gr.rotation_scale);
  h5::writeAttrU8(g, "contacts_available", gr.contacts_available ? 1 : 0);
  h5::writeDataset(g, "pose", h5::Type::kF64, gr.pose.data(), n, 7);
  h5::writeDataset(g, "joints", h5::Type::kF64, gr.joints.data(), n,
                   static_cast<std::size_t>(gr.joints.cols()));
  h5::writeVector(g, "force_closure", h5::Type::kU8, gr.force_closure.data(), n);
  h5::writeVector(g, "epsilon", h5::Type::kF64, gr.epsilon.data(), n);
  h5::writeVector(g, "volume", h5::Type::kF64, gr.volume.data(), n);
  h5::writeVector(g, "contact_offsets", h5::Type::kI64, gr.contact_offsets.data(), n + 1);
  h5::writeDataset(g, "contact_points", h5::Type::kF64, gr.contact_points.data(), m, 3);
  h5::writeDataset(g, "contact_normals", h5::Type::kF64, gr.contact_normals.data(), m, 3);
  h5::writeVector(g, "contact_depths", h5::Type::kF64, gr.contact_depths.data(), m);
  h5::writeVector(g, "contact_links", h5::Type::kI32, gr.contact_links.data(), m);
  if (!map.clustering) return;
  const ClusteringResult& c = *map.clustering;
  h5::writeVector(g, "cluster", h5::Type::kI32, c.labels.data(), n);

  const std::size_t k = c.clusters.size();
  std::vector<std::int32_t> size(k), representative(k);
  std::vector<double> mean_epsilon(k), best_epsilon(k);
  RowMatrixXd mean_pose(static_cast<Eigen::Index>(k), 7);
  RowMatrixXd bounds_min(static_cast<Eigen::Index>(k), 3),
      bounds_max(static_cast<Eigen::Index>(k), 3);
  for (std::size_t j = 0; j < k; ++j) {
    const ClusterSummary& s = c.clusters[j];
    const auto r = static_cast<Eigen::Index>(j);
    size[j] = s.size;
    representative[j] = s.representative;
    mean_epsilon[j] = s.mean_epsilon;
    best_epsilon[j] = s.best_epsilon;
    mean_pose.row(r) = s.mean_pose.toVector7().transpose();
    bounds_min.row(r) = s.bounds_min.transpose();
    bounds_max.row(r) = s.bounds_max.transpose();
  }
  Id cg = h5::createGroup(file, "clusters");
  h5::writeVector(cg, "size", h5::Type::kI32, size.data(), k);
  h5::writeVector(cg, "representative", h5::Type::kI32, representative.data(), k);
  h5::writeDataset(cg, "mean_pose", h5::Type::kF64, mean_pose.data(), k, 7);
  h5::writeVector(cg, "mean_epsilon", h5::Type::kF64, mean_epsilon.data(), k);
  h5::writeVector(cg, "best_epsilon", h5::Type::kF64, best_epsilon.data(), k);
  h5::writeDataset(cg, "bounds_min", h5::Type::kF64, bounds_min.data(), k, 3);
  h5::writeDataset(cg, "bounds_max", h5::Type::kF64, bounds_max.data(), k, 3);

  Id lg = h5::createGroup(file, "clustering");
  h5::writeAttr(lg, "method", std::string(toString(c.method)));
  h5::writeAttr(lg, "rotation_scale", c.rotation_scale);
  h5::writeAttr(lg, "threshold", c.threshold);
  h5::writeAttrInt(lg, "min_size", c.min_size);
  const RowMatrixXd linkage = c.linkage;
  h5::writeDataset(lg, "linkage", h5::Type::kF64, linkage.data(),
                   static_cast<std::size_t>(linkage.rows()), 4);
}

void writeValidation(hid_t file, const TaskMapData& map) {
  if (!map.validation) return;
  const MapValidation& v = *map.validation;
  const std::size_t n = map.grasps.size();
  Id g = h5::openGroup(file, "/grasps");
  h5::writeVector(g, "hold", h5::Type::kU8, v.hold.data(), n);
  h5::writeVector(g, "hold_status", h5::Type::kU8, v.status.data(), n);
  h5::writeVector(g, "hold_translation", h5::Type::kF64, v.translation.data(), n);
  h5::writeVector(g, "hold_rotation", h5::Type::kF64, v.rotation.data(), n);
  h5::writeVector(g, "hold_direction", h5::Type::kI32, v.direction.data(), n);
  Id vg = h5::createGroup(file, "validation");
  h5::writeAttr(vg, "protocol", v.protocol);
  h5::writeAttr(vg, "engine", v.engine);
  h5::writeAttr(vg, "params_json", v.params_json);
  h5::writeAttrUInt(vg, "tested", v.tested());
  h5::writeAttrUInt(vg, "holding", v.holding());
  if (v.robust_json.empty()) return;
  h5::writeVector(g, "robust", h5::Type::kU8, v.robust.data(), n);
  h5::writeVector(g, "robust_share", h5::Type::kF64, v.robust_share.data(), n);
  h5::writeVector(g, "hold_push_translation", h5::Type::kF64, v.push_translation.data(), n);
  h5::writeVector(g, "hold_push_rotation", h5::Type::kF64, v.push_rotation.data(), n);
  h5::writeDataset(g, "robust_variants", h5::Type::kU8, v.variant_held.data(), n, v.variantCount());
  h5::writeAttr(vg, "robust_json", v.robust_json);
  h5::writeAttrUInt(vg, "robust", v.robustCount());
}

void writeFile(const std::string& tmp, const TaskMapData& map) {
  Id fcpl = h5::mapFileCreation(seal::kSealBytes);
  Id fapl = h5::mapFileAccess();
  Id file = h5::checked(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, fcpl, fapl), H5Fclose,
                        "cannot create file (directory missing or not writable?)");
  h5::writeAttr(file, "format", std::string(kFormat));
  h5::writeAttrInt(file, "schema_version", kMapSchemaVersion);
  h5::writeAttr(file, "generator", map.generator);
  h5::writeAttr(file, "created_utc", map.created_utc);
  writeObject(file, map.object);
  writeHand(file, map.hand);
  writeSampling(file, map.sampling);
  writeQuality(file, map.quality);
  writeGrasps(file, map);
  writeValidation(file, map);
  h5::check(H5Fflush(file, H5F_SCOPE_GLOBAL), "cannot flush the file (disk full?)");
  if (!file.reset()) throw Error("cannot close the file (disk full?)");
  seal::stampFile(tmp);
}

// ---------------------------------------------------------------- reading

void readObject(hid_t file, MapObject& o) {
  Id g = h5::openGroup(file, "/object");
  o.name = h5::readAttrString(g, "/object", "name");
  o.source_sha256 = h5::readAttrString(g, "/object", "source_sha256");
  o.scale = h5::readAttrDouble(g, "/object", "scale");
  o.volume = h5::readAttrDouble(g, "/object", "volume");
  const auto com = h5::readAttrVector(g, "/object", "center_of_mass", 3);
  o.center_of_mass = Eigen::Vector3d(com[0], com[1], com[2]);
  o.torque_scale = h5::readAttrDouble(g, "/object", "torque_scale");
  o.vertices = toRows(h5::readF64(file, "/object/vertices", 2, 3), 3);
  const auto faces = h5::readI64(file, "/object/faces", 2, 3);
  o.faces.resize(static_cast<Eigen::Index>(faces.rows()), 3);
  std::copy(faces.values.begin(), faces.values.end(), o.faces.data());
}

void readHand(hid_t file, MapHand& h) {
  Id g = h5::openGroup(file, "/hand");
  h.name = h5::readAttrString(g, "/hand", "name");
  h.urdf_sha256 = h5::readAttrString(g, "/hand", "urdf_sha256");
  h.joint_names = h5::readStrings(file, "/hand/joint_names");
  if (h5::exists(g, "link_names")) h.link_names = h5::readStrings(file, "/hand/link_names");
}

void readSampling(hid_t file, MapSampling& s) {
  Id g = h5::openGroup(file, "/sampling");
  s.sampler = h5::readAttrString(g, "/sampling", "sampler");
  s.seed = h5::readAttrUInt(g, "/sampling", "seed");
  s.trials = h5::readAttrUInt(g, "/sampling", "trials");
  s.params_json = h5::readAttrString(g, "/sampling", "params_json");
  const std::string prefix = kOutcomePrefix;
  for (const auto& name : h5::attrNames(g, "/sampling"))
    if (name.compare(0, prefix.size(), prefix) == 0)
      s.outcomes[name.substr(prefix.size())] = h5::readAttrUInt(g, "/sampling", name);
}

void readQuality(hid_t file, MapQuality& q) {
  Id g = h5::openGroup(file, "/quality");
  q.friction = h5::readAttrDouble(g, "/quality", "friction");
  const std::int64_t edges = h5::readAttrInt(g, "/quality", "cone_edges");
  if (edges < 0 || edges > std::numeric_limits<int>::max())
    throw Error("/quality attribute cone_edges is out of range");
  q.cone_edges = static_cast<int>(edges);
  q.contact_model = h5::readAttrString(g, "/quality", "contact_model");
}

std::vector<double> vectorOf(const h5::Array<double>& a) {
  return a.values;
}

void readGrasps(hid_t file, TaskMapData& map) {
  MapGrasps& gr = map.grasps;
  Id g = h5::openGroup(file, "/grasps");
  gr.rotation_scale = h5::readAttrDouble(g, "/grasps", "rotation_scale");
  gr.contacts_available = h5::readAttrInt(g, "/grasps", "contacts_available") != 0;
  gr.pose = toRows(h5::readF64(file, "/grasps/pose", 2, 7), 7);
  const auto joints = h5::readF64(file, "/grasps/joints", 2);
  gr.joints = toRows(joints, static_cast<std::size_t>(joints.dims[1]));
  const auto fc = h5::readI64(file, "/grasps/force_closure", 1);
  gr.force_closure.clear();
  for (std::size_t i = 0; i < fc.values.size(); ++i) {
    if (fc.values[i] != 0 && fc.values[i] != 1)
      throw Error("/grasps/force_closure: entry " + std::to_string(i) + " is neither 0 nor 1");
    gr.force_closure.push_back(static_cast<std::uint8_t>(fc.values[i]));
  }
  gr.epsilon = vectorOf(h5::readF64(file, "/grasps/epsilon", 1));
  gr.volume = vectorOf(h5::readF64(file, "/grasps/volume", 1));
  gr.contact_offsets = h5::readI64(file, "/grasps/contact_offsets", 1).values;
  if (gr.contact_offsets.empty()) throw Error("/grasps/contact_offsets: must not be empty");
  gr.contact_points = toRows(h5::readF64(file, "/grasps/contact_points", 2, 3), 3);
  gr.contact_normals = toRows(h5::readF64(file, "/grasps/contact_normals", 2, 3), 3);
  gr.contact_depths = vectorOf(h5::readF64(file, "/grasps/contact_depths", 1));
  const auto links = h5::readI64(file, "/grasps/contact_links", 1);
  gr.contact_links.clear();
  for (std::size_t i = 0; i < links.values.size(); ++i) {
    if (links.values[i] < -1 || links.values[i] > std::numeric_limits<std::int32_t>::max())
      throw Error("/grasps/contact_links: entry " + std::to_string(i) + " is out of range");
    gr.contact_links.push_back(static_cast<std::int32_t>(links.values[i]));
  }
}

void readClustering(hid_t file, TaskMapData& map) {
  map.clustering.reset();
  if (!h5::exists(file, "/clustering")) return;
  ClusteringResult c;
  Id lg = h5::openGroup(file, "/clustering");
  c.method = linkageByName(h5::readAttrString(lg, "/clustering", "method"));
  c.rotation_scale = h5::readAttrDouble(lg, "/clustering", "rotation_scale");
  c.threshold = h5::readAttrDouble(lg, "/clustering", "threshold");
  const std::int64_t min_size = h5::readAttrInt(lg, "/clustering", "min_size");
  if (min_size < 0 || min_size > std::numeric_limits<int>::max())
    throw Error("/clustering attribute min_size is out of range");
  c.min_size = static_cast<int>(min_size);
  const auto linkage = h5::readF64(file, "/clustering/linkage", 2, 4);
  c.linkage.resize(static_cast<Eigen::Index>(linkage.rows()), 4);
  for (std::size_t r = 0; r < linkage.rows(); ++r)
    for (std::size_t col = 0; col < 4; ++col)
      c.linkage(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(col)) =
          linkage.values[r * 4 + col];

  auto toInt = [](const std::vector<std::int64_t>& v, const std::string& name) {
    std::vector<int> out;
    out.reserve(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (v[i] < std::numeric_limits<int>::min() || v[i] > std::numeric_limits<int>::max())
        throw Error(name + ": entry " + std::to_string(i) + " is out of range");
      out.push_back(static_cast<int>(v[i]));
    }
    return out;
  };
  c.labels = toInt(h5::readI64(file, "/grasps/cluster", 1).values, "/grasps/cluster");
  const auto size = toInt(h5::readI64(file, "/clusters/size", 1).values, "/clusters/size");
  const std::size_t k = size.size();
  const auto rep =
      toInt(h5::readI64(file, "/clusters/representative", 1).values, "/clusters/representative");
  const auto mean_pose = h5::readF64(file, "/clusters/mean_pose", 2, 7);
  const auto mean_eps = h5::readF64(file, "/clusters/mean_epsilon", 1);
  const auto best_eps = h5::readF64(file, "/clusters/best_epsilon", 1);
  const auto bmin = h5::readF64(file, "/clusters/bounds_min", 2, 3);
  const auto bmax = h5::readF64(file, "/clusters/bounds_max", 2, 3);
  auto requireK = [k](std::size_t rows, const std::string& name) {
    if (rows != k)
      throw Error(name + ": has " + std::to_string(rows) + " rows, expected " + std::to_string(k) +
                  " (one per cluster, as /clusters/size)");
  };
  requireK(rep.size(), "/clusters/representative");
  requireK(mean_pose.rows(), "/clusters/mean_pose");
  requireK(mean_eps.rows(), "/clusters/mean_epsilon");
  requireK(best_eps.rows(), "/clusters/best_epsilon");
  requireK(bmin.rows(), "/clusters/bounds_min");
  requireK(bmax.rows(), "/clusters/bounds_max");
  c.clusters.resize(k);
  for (std::size_t j = 0; j < k; ++j) {
    ClusterSummary& s = c.clusters[j];
    s.size = size[j];
    s.representative = rep[j];
    const double* p = mean_pose.values.data() + j * 7;
    s.mean_pose.position = Eigen::Vector3d(p[0], p[1], p[2]);
    s.mean_pose.orientation = Eigen::Quaterniond(p[3], p[4], p[5], p[6]);
    s.mean_epsilon = mean_eps.values[j];
    s.best_epsilon = best_eps.values[j];
    s.bounds_min = Eigen::Vector3d(bmin.values.data() + j * 3);
    s.bounds_max = Eigen::Vector3d(bmax.values.data() + j * 3);
  }
  map.clustering = std::move(c);
}

/// Integers of a 1-D dataset, each checked to lie in [lo, hi].
template <class T>
std::vector<T> readIntsIn(hid_t file, const std::string& path, std::int64_t lo, std::int64_t hi) {
  const auto a = h5::readI64(file, path, 1);
  std::vector<T> out;
  out.reserve(a.values.size());
  for (std::size_t i = 0; i < a.values.size(); ++i) {
    if (a.values[i] < lo || a.values[i] > hi)
      throw Error(path + ": entry " + std::to_string(i) + " is out of range");
    out.push_back(static_cast<T>(a.values[i]));
  }
  return out;
}

void readValidation(hid_t file, TaskMapData& map) {
  map.validation.reset();
  if (!h5::exists(file, "/validation")) return;
  MapValidation v;
  Id vg = h5::openGroup(file, "/validation");
  v.protocol = h5::readAttrString(vg, "/validation", "protocol");
  v.engine = h5::readAttrString(vg, "/validation", "engine");
  v.params_json = h5::readAttrString(vg, "/validation", "params_json");
  v.hold = readIntsIn<std::uint8_t>(file, "/grasps/hold", 0, 255);
  v.status = readIntsIn<std::uint8_t>(file, "/grasps/hold_status", 0, 255);
  v.translation = vectorOf(h5::readF64(file, "/grasps/hold_translation", 1));
  v.rotation = vectorOf(h5::readF64(file, "/grasps/hold_rotation", 1));
  v.direction = readIntsIn<std::int32_t>(file, "/grasps/hold_direction", -1, 5);
  if (h5::hasAttr(vg, "robust_json")) {
    v.robust_json = h5::readAttrString(vg, "/validation", "robust_json");
    v.robust = readIntsIn<std::uint8_t>(file, "/grasps/robust", 0, 255);
    v.robust_share = vectorOf(h5::readF64(file, "/grasps/robust_share", 1));
    v.push_translation = vectorOf(h5::readF64(file, "/grasps/hold_push_translation", 1));
    v.push_rotation = vectorOf(h5::readF64(file, "/grasps/hold_push_rotation", 1));
    const std::size_t variants = v.variantCount();
    if (variants == 0) throw Error("/validation attribute robust_json names no variants");
    const auto held = h5::readI64(file, "/grasps/robust_variants", 2, variants);
    for (std::size_t i = 0; i < held.values.size(); ++i) {
      if (held.values[i] < 0 || held.values[i] > 255)
        throw Error("/grasps/robust_variants: entry " + std::to_string(i) + " is out of range");
      v.variant_held.push_back(static_cast<std::uint8_t>(held.values[i]));
    }
  }
  map.validation = std::move(v);
}

TaskMapData readFile(hid_t file) {
  if (!h5::hasAttr(file, "format") ||
      h5::readAttrString(file, "/", "format") != std::string(kFormat))
    throw Error("not a task map (root attribute format is not \"taskmap\")");
  const std::int64_t version = h5::readAttrInt(file, "/", "schema_version");
  if (version > kMapSchemaVersion)
    throw Error("written by a newer taskmap (schema " + std::to_string(version) +
                "); upgrade taskmap to read it (this one reads schema " +
                std::to_string(kMapSchemaVersion) + ")");
  if (version < 1) throw Error("invalid schema_version " + std::to_string(version));
  // Schema 1 (unsealed, variable-length strings) reads the same once sealed with `taskmap seal`.
  TaskMapData map;
  map.generator = h5::readAttrString(file, "/", "generator");
  map.created_utc = h5::readAttrString(file, "/", "created_utc");
  readObject(file, map.object);
  readHand(file, map.hand);
  readSampling(file, map.sampling);
  readQuality(file, map.quality);
  readGrasps(file, map);
  readClustering(file, map);
  readValidation(file, map);
  map.validate();
  return map;
}

std::string tempPathFor(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
}

}  // namespace

void writeMap(const std::string& path, const TaskMapData& map) {
  try {
    map.validate();
  } catch (const Error& e) {
    throw Error("refusing to write invalid task map '" + path + "': " + e.what());
  }
  const std::string tmp = tempPathFor(path);
  std::lock_guard<std::mutex> lock(h5::hdf5Mutex());
  h5::silenceErrors();
  try {
    writeFile(tmp, map);
  } catch (const Error& e) {
    std::remove(tmp.c_str());
    throw Error("cannot write task map '" + path + "': " + e.what());
  }
  commitTemporaryFile(tmp, path, "cannot write task map '" + path + "'");
}

TaskMapData readMap(const std::string& path) {
  try {
    // The one verified path: HDF5 parses only the in-memory bytes whose seal was checked.
    const std::string bytes = seal::readVerified(path);
    std::lock_guard<std::mutex> lock(h5::hdf5Mutex());
    h5::silenceErrors();
    Id file = h5::openImage(bytes, "cannot open the sealed content as HDF5");
    return readFile(file);
  } catch (const Error& e) {
    throw Error("task map '" + path + "': " + e.what());
  }
}

void sealMap(const std::string& path) {
  try {
    const std::string bytes = seal::resealed(seal::readWhole(path, kMaxSealBytes));
    // The unverified file is validated in a child with memory and CPU limits
    // (taskmap/core/bounded_child.hpp): a 21 KB file declaring a sparse 100M x 7 dataset is
    // refused instead of exhausting the caller (taskmap.seal in Python).
    runBounded(
        [&bytes]() {
          std::lock_guard<std::mutex> lock(h5::hdf5Mutex());
          h5::silenceErrors();
          Id file = h5::openImage(bytes, "cannot open the file as HDF5 (damaged?)");
          readFile(file);  // validates every dataset; throws on the first violation
          return std::string();
        },
        bytes.size(), "validating it");
    writeFileAtomically(path, bytes, "cannot write the sealed file");
  } catch (const Error& e) {
    throw Error("cannot seal task map '" + path + "': " + e.what());
  }
}

std::string mapCreationTime(bool wall_clock) {
  std::time_t t = 0;
  const char* epoch = std::getenv("SOURCE_DATE_EPOCH");
  if (epoch != nullptr && *epoch != '\0') {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(epoch, &end, 10);
    if (*end != '\0' || errno != 0 || v < 0 || v > 253402300799LL)
      throw Error("SOURCE_DATE_EPOCH='" + std::string(epoch) +
                  "' is not a number of seconds since 1970-01-01 (unset it or give e.g. "
                  "1700000000)");
    t = static_cast<std::time_t>(v);
  } else if (wall_clock) {
    t = std::time(nullptr);
  } else {
    return "";
  }
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

}  // namespace taskmap
