// ACRONYM per-object grasp files on mapstore's HDF5 layer (hdf5_io.hpp; layout: acronym.hpp).
#include "taskmap/mapstore/acronym.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <mutex>
#include <system_error>

#include <unistd.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "hdf5_io.hpp"
#include "map_seal.hpp"
#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/input_file.hpp"
#include "taskmap/mapstore/map_file.hpp"

#ifndef TASKMAP_VERSION
#define TASKMAP_VERSION "unknown"
#endif

namespace taskmap {
namespace {

// Foreign files carry no seal: they are read whole into memory (at most kMaxAcronymBytes)
// and every dataset may declare at most what its file could hold after deflate's best ratio.
constexpr std::size_t kMaxAcronymBytes = std::size_t{1} << 30;
constexpr hsize_t kMaxInflation = 1032;

/// The datasets of one ACRONYM file on the HDF5 layer (hdf5_io.hpp); its errors name the file
/// and ask whether it is an ACRONYM grasp file.
class Reader {
 public:
  Reader(hid_t file, std::string path, std::size_t file_bytes)
      : file_(file), path_(std::move(path)), max_values_((file_bytes + 4096) * kMaxInflation / 8) {}

  bool has(const std::string& name) const { return h5::exists(file_, name); }

  /// Numeric dataset as doubles with its shape; any integer or float type.
  std::vector<double> doubles(const std::string& name, std::vector<hsize_t>* dims) const {
    h5::Array<double> a = guarded([&] { return h5::readAnyNumbers(file_, name, max_values_); });
    *dims = std::move(a.dims);
    return std::move(a.values);
  }

  double scalar(const std::string& name) const {
    std::vector<hsize_t> dims;
    const std::vector<double> v = doubles(name, &dims);
    if (v.size() != 1) fail(name, "should hold one number but holds " + std::to_string(v.size()));
    return v[0];
  }

  std::string string(const std::string& name) const {
    return guarded([&] { return h5::readOneString(file_, name); });
  }

  [[noreturn]] void fail(const std::string& name, const std::string& what) const {
    failWith("dataset " + name + " " + what);
  }

 private:
  [[noreturn]] void failWith(const std::string& message) const {
    throw Error("'" + path_ + "': " + message + "; is this an ACRONYM grasp file?");
  }
  /// read() with its Error ("dataset <name> <problem>") naming the file.
  template <typename Read>
  auto guarded(Read read) const -> decltype(read()) {
    try {
      return read();
    } catch (const Error& e) {
      failWith(e.what());
    }
  }

  hid_t file_;
  std::string path_;
  hsize_t max_values_;
};

/// Throws unless t is a finite rigid transform.
void checkBaseToPalm(const Eigen::Isometry3d& t, const char* who) {
  const Eigen::Matrix3d r = t.linear();
  if (!t.matrix().allFinite() || (r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-9 ||
      r.determinant() < 0) {
    throw Error(std::string(who) + ": base_to_palm must be a finite rigid transform");
  }
}

/// The datasets of an ACRONYM file (acronym.hpp) written into `file` (under hdf5Mutex()):
/// grasp transforms (N x 4 x 4, gripper base in the object frame) and success flags, our
/// epsilon, the object's file, scale and mass properties, the gripper's type and base-to-palm.
void writeAcronymDatasets(hid_t file, const TaskMapData& map, const AcronymExportOptions& options,
                          const std::vector<double>& transforms,
                          const std::vector<std::int64_t>& success,
                          const Eigen::Matrix3d& inertia) {
  using h5::Type;
  const std::size_t n = map.grasps.size();
  const double volume = map.object.volume;
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> inertia_rm = inertia;
  const Eigen::Matrix<double, 4, 4, Eigen::RowMajor> b = options.base_to_palm.matrix();
  const auto scalar = [&](const char* name, double v) {
    h5::writePlain(file, name, Type::kF64, &v, {});
  };
  h5::writePlain(file, "grasps/transforms", Type::kF64, transforms.data(), {n, 4, 4});
  h5::writePlain(file, "grasps/qualities/flex/object_in_gripper", Type::kI64, success.data(),
                 {success.size()});
  h5::writePlain(file, "grasps/qualities/taskmap/epsilon", Type::kF64, map.grasps.epsilon.data(),
                 {n});
  h5::writePlainString(
      file, "object/file",
      options.object_file.empty() ? map.object.name + ".obj" : options.object_file);
  scalar("object/scale", map.object.scale);
  scalar("object/density", options.density);
  scalar("object/mass", options.density * volume);
  scalar("object/friction", map.quality.friction);
  scalar("object/volume", volume);
  h5::writePlain(file, "object/com", Type::kF64, map.object.center_of_mass.data(), {3});
  h5::writePlain(file, "object/inertia", Type::kF64, inertia_rm.data(), {3, 3});
  h5::writePlainString(file, "gripper/type", map.hand.name);
  h5::writePlain(file, "gripper/configuration", Type::kF64, nullptr, {0});
  h5::writePlain(file, "gripper/taskmap_base_to_palm", Type::kF64, b.data(), {4, 4});
}

}  // namespace

Eigen::Isometry3d acronymFrankaBaseToPalm() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(0, 0, kAcronymFrankaPalmOffset);
  return t;
}

void AcronymExportOptions::validate() const {
  if (!(density > 0) || !std::isfinite(density)) {
    throw Error("ACRONYM export: density must be a positive number of kg/m^3");
  }
  checkBaseToPalm(base_to_palm, "ACRONYM export");
}

void AcronymImportOptions::validate() const {
  clustering.validate();
  checkBaseToPalm(base_to_palm, "ACRONYM import");
}

Eigen::Matrix3d meshInertia(
    const RowMatrixXd& vertices,
    const Eigen::Matrix<std::int64_t, Eigen::Dynamic, 3, Eigen::RowMajor>& faces,
    const Eigen::Vector3d& center_of_mass, double density) {
  // Signed tetrahedra (origin, a, b, c): second moment det * A C0 A^T with C0 the canonical
  // tetrahedron's covariance, first moment det / 24 * (a + b + c), volume det / 6.
  Eigen::Matrix3d c0;
  c0 << 2, 1, 1, 1, 2, 1, 1, 1, 2;
  c0 /= 120.0;
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  double volume = 0.0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    Eigen::Matrix3d a;
    for (int k = 0; k < 3; ++k) a.col(k) = vertices.row(faces(f, k)).transpose();
    const double det = a.determinant();
    second += det * a * c0 * a.transpose();
    first += det / 24.0 * a.rowwise().sum();
    volume += det / 6.0;
  }
  const Eigen::Vector3d& c = center_of_mass;
  // Second moment about c: S - x c^T - c x^T + V c c^T, with x the first moment.
  const Eigen::Matrix3d s = density * (second - first * c.transpose() - c * first.transpose() +
                                       volume * c * c.transpose());
  return s.trace() * Eigen::Matrix3d::Identity() - s;
}

void writeAcronym(const std::string& path, const TaskMapData& map,
                  const AcronymExportOptions& options) {
  options.validate();
  map.validate();
  const MapGrasps& g = map.grasps;
  const std::size_t n = g.size();
  std::vector<double> transforms(n * 16);
  const Eigen::Isometry3d palm_to_base = options.base_to_palm.inverse();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Matrix4d t = (g.poseAt(i).toIsometry() * palm_to_base).matrix();
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        transforms[i * 16 + static_cast<std::size_t>(r * 4 + c)] = t(r, c);
  }
  std::vector<std::int64_t> success(g.force_closure.begin(), g.force_closure.end());
  const Eigen::Matrix3d inertia = meshInertia(map.object.vertices, map.object.faces,
                                              map.object.center_of_mass, options.density);

  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  {
    std::lock_guard<std::mutex> lock(h5::hdf5Mutex());
    h5::silenceErrors();
    const h5::Id fcpl = h5::mapFileCreation(0);  // no user block; no root-group times
    h5::Id file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT), H5Fclose);
    if (file.get() < 0) {
      throw Error("cannot write '" + path + "': cannot create '" + tmp +
                  "'; check that the directory exists and is writable");
    }
    try {
      writeAcronymDatasets(file, map, options, transforms, success, inertia);
      if (!file.reset()) throw Error("HDF5 failed to close the file");
    } catch (const Error& e) {
      file.reset();
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw Error("cannot write '" + path + "': " + e.what());
    }
  }
  commitTemporaryFile(tmp, path, "cannot write '" + path + "'");
}

AcronymGrasps readAcronym(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) requireRegularFile(path, "ACRONYM file");
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw Error("ACRONYM file '" + path + "' does not exist; give the path of a grasp file (.h5)");
  }
  AcronymGrasps out;
  out.path = path;
  std::string bytes;
  try {
    bytes = seal::readWhole(path, kMaxAcronymBytes);
  } catch (const Error& e) {
    throw Error("ACRONYM file '" + path + "': " + e.what());
  }
  if (!seal::hasHdf5Signature(bytes)) {
    throw Error("'" + path + "' is not an HDF5 file; give an ACRONYM grasp file (.h5)");
  }
  std::lock_guard<std::mutex> lock(h5::hdf5Mutex());
  h5::silenceErrors();
  h5::Id file = h5::openImage(bytes, "cannot open '" + path + "' (corrupt HDF5 file?)");
  Reader r(file, path, bytes.size());
  std::vector<hsize_t> dims;
  const std::vector<double> t = r.doubles("grasps/transforms", &dims);
  if (dims.size() != 3 || dims[1] != 4 || dims[2] != 4) {
    r.fail("grasps/transforms", "should have shape N x 4 x 4");
  }
  const std::size_t n = dims[0];
  out.transforms.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int row = 0; row < 4; ++row)
      for (int c = 0; c < 4; ++c)
        out.transforms[i](row, c) = t[i * 16 + static_cast<std::size_t>(row * 4 + c)];
  }
  const std::string success_name = "grasps/qualities/flex/object_in_gripper";
  const std::vector<double> s = r.doubles(success_name, &dims);
  if (dims.size() != 1 || dims[0] != n) {
    r.fail(success_name, "should hold one value per transform (" + std::to_string(n) + ")");
  }
  out.success.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(s[i])) r.fail(success_name, "holds a non-finite value");
    out.success[i] = s[i] != 0.0 ? 1 : 0;
  }
  const std::string eps_name = "grasps/qualities/taskmap/epsilon";
  if (r.has(eps_name)) {
    std::vector<double> e = r.doubles(eps_name, &dims);
    if (dims.size() != 1 || dims[0] != n) r.fail(eps_name, "should hold one value per transform");
    out.epsilon = std::move(e);
  }
  if (r.has("object/file")) out.object_file = r.string("object/file");
  if (r.has("object/scale")) out.object_scale = r.scalar("object/scale");
  if (!(out.object_scale > 0) || !std::isfinite(out.object_scale)) {
    r.fail("object/scale", "must be a positive number");
  }
  auto optional_scalar = [&](const char* name, std::optional<double>& field) {
    if (r.has(name)) field = r.scalar(name);
  };
  optional_scalar("object/mass", out.object_mass);
  optional_scalar("object/density", out.object_density);
  optional_scalar("object/friction", out.object_friction);
  optional_scalar("object/volume", out.object_volume);
  if (r.has("object/com")) {
    const std::vector<double> c = r.doubles("object/com", &dims);
    if (c.size() != 3) r.fail("object/com", "should hold 3 numbers");
    out.object_com = Eigen::Vector3d(c[0], c[1], c[2]);
  }
  if (r.has("gripper/type")) out.gripper_type = r.string("gripper/type");
  if (r.has("gripper/configuration")) {
    out.gripper_configuration = r.doubles("gripper/configuration", &dims);
  }
  return out;
}

TaskMapData acronymToMap(const AcronymGrasps& in, const MapObject& object,
                         const AcronymImportOptions& options) {
  options.validate();
  const std::size_t total = in.transforms.size();
  if (in.success.size() != total) {
    throw Error("ACRONYM import: " + std::to_string(total) + " transforms but " +
                std::to_string(in.success.size()) + " object_in_gripper values");
  }
  if (in.epsilon && in.epsilon->size() != total) {
    throw Error("ACRONYM import: epsilon does not hold one value per transform");
  }
  std::vector<std::size_t> keep;
  for (std::size_t i = 0; i < total; ++i) {
    if (!options.successful_only || in.success[i] != 0) keep.push_back(i);
  }
  if (keep.empty()) {
    throw Error("ACRONYM import from '" + in.path + "': no grasps to import" +
                (options.successful_only ? " (no successful grasp)" : ""));
  }
  TaskMapData m;
  m.generator = std::string("taskmap ") + TASKMAP_VERSION;
  m.created_utc = mapCreationTime();
  m.object = object;
  m.hand.name = in.gripper_type.empty() ? "acronym_gripper" : in.gripper_type;
  m.sampling.sampler = "acronym";
  m.sampling.seed = 0;
  m.sampling.trials = total;
  const auto successes =
      static_cast<std::uint64_t>(std::count(in.success.begin(), in.success.end(), 1));
  if (successes > 0) m.sampling.outcomes["force_closure"] = successes;
  if (total > successes) m.sampling.outcomes["not_force_closure"] = total - successes;
  nlohmann::json params = {
      {"imported_from", "acronym"},
      {"source", in.path},
      {"object_file", in.object_file},
      {"object_scale", in.object_scale},
      {"successful_only", options.successful_only},
      {"base_to_palm",
       {options.base_to_palm.translation().x(), options.base_to_palm.translation().y(),
        options.base_to_palm.translation().z(),
        Eigen::Quaterniond(options.base_to_palm.linear()).w(),
        Eigen::Quaterniond(options.base_to_palm.linear()).x(),
        Eigen::Quaterniond(options.base_to_palm.linear()).y(),
        Eigen::Quaterniond(options.base_to_palm.linear()).z()}},
      {"force_closure", "ACRONYM grasps/qualities/flex/object_in_gripper"},
      {"epsilon", in.epsilon ? "taskmap epsilon stored in the file"
                             : "object_in_gripper as 0 or 1 (no epsilon "
                               "in ACRONYM)"}};
  m.sampling.params_json = params.dump();
  m.quality.friction = in.object_friction.value_or(m.quality.friction);
  m.quality.cone_edges = 0;
  m.quality.contact_model = "none";

  const auto n = static_cast<Eigen::Index>(keep.size());
  MapGrasps& g = m.grasps;
  g.pose.resize(n, 7);
  g.joints.resize(n, 0);
  g.force_closure.resize(keep.size());
  g.epsilon.resize(keep.size());
  g.volume.assign(keep.size(), 0.0);
  g.contact_offsets.assign(keep.size() + 1, 0);
  g.contact_points.resize(0, 3);
  g.contact_normals.resize(0, 3);
  g.contacts_available = false;
  g.rotation_scale = options.clustering.rotation_scale;
  std::vector<Pose> poses;
  poses.reserve(keep.size());
  for (std::size_t j = 0; j < keep.size(); ++j) {
    const std::size_t i = keep[j];
    const Eigen::Matrix4d& t = in.transforms[i];
    const Eigen::Matrix3d r = t.topLeftCorner<3, 3>();
    const bool rigid =
        t.allFinite() && (r.transpose() * r - Eigen::Matrix3d::Identity()).norm() < 1e-6 &&
        r.determinant() > 0 && (t.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() < 1e-9;
    if (!rigid) {
      throw Error("ACRONYM import from '" + in.path + "': grasps/transforms[" + std::to_string(i) +
                  "] is not a rigid transform");
    }
    Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
    base.translation() = t.topRightCorner<3, 1>();
    base.linear() = Eigen::Quaterniond(r).normalized().toRotationMatrix();
    const Eigen::Isometry3d palm = base * options.base_to_palm;
    Pose p;
    p.position = palm.translation();
    p.orientation = Eigen::Quaterniond(palm.linear()).normalized();
    g.pose.row(static_cast<Eigen::Index>(j)) = p.toVector7().transpose();
    g.force_closure[j] = in.success[i];
    g.epsilon[j] = in.epsilon ? (*in.epsilon)[i] : static_cast<double>(in.success[i]);
    poses.push_back(p);
  }
  if (options.cluster && keep.size() >= 2) {
    ClusteringOptions co = options.clustering;
    m.clustering = clusterGrasps(poses, g.epsilon, co);
  }
  m.validate();
  return m;
}

}  // namespace taskmap
