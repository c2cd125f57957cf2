// ACRONYM per-object grasp files (HDF5 C API; see acronym.hpp for the layout).
#include "taskmap/mapstore/acronym.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstring>
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

// Owning HDF5 id with its close function.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& other) noexcept : id_(other.id_), closer_(other.closer_) { other.id_ = -1; }
  Handle& operator=(Handle&&) = delete;
  ~Handle() {
    if (id_ >= 0) closer_(id_);
  }
  bool valid() const { return id_ >= 0; }
  operator hid_t() const { return id_; }  // NOLINT: used as a plain hid_t in HDF5 calls
  /// Closes now; false when closing failed.
  bool close() {
    const herr_t r = id_ >= 0 ? closer_(id_) : 0;
    id_ = -1;
    return r >= 0;
  }

 private:
  hid_t id_;
  Closer closer_;
};

// ---------------------------------------------------------------- writing

class Writer {
 public:
  Writer(hid_t file, std::string path) : file_(file), path_(std::move(path)) {
    H5Pset_create_intermediate_group(lcpl_, 1);
  }

  void doubles(const std::string& name, const std::vector<hsize_t>& dims, const double* data) {
    Handle space(dims.empty()
                     ? H5Screate(H5S_SCALAR)
                     : H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
                 H5Sclose);
    write(name, space, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, data);
  }
  void scalar(const std::string& name, double v) { doubles(name, {}, &v); }
  void int64s(const std::string& name, const std::vector<std::int64_t>& v) {
    const hsize_t dims[1] = {v.size()};
    Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose);
    write(name, space, H5T_STD_I64LE, H5T_NATIVE_INT64, v.data());
  }
  // Scalar variable-length UTF-8 string (what h5py writes for `f[name] = "text"`).
  void string(const std::string& name, const std::string& value) {
    Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(type, H5T_VARIABLE);
    H5Tset_cset(type, H5T_CSET_UTF8);
    Handle space(H5Screate(H5S_SCALAR), H5Sclose);
    const char* ptr = value.c_str();
    write(name, space, type, type, &ptr);
  }

 private:
  void write(const std::string& name, hid_t space, hid_t file_type, hid_t mem_type,
             const void* data) {
    createParents(name);
    Handle ds(H5Dcreate2(file_, name.c_str(), file_type, space, lcpl_, dcpl_, H5P_DEFAULT),
              H5Dclose);
    // Empty datasets are created without writing (HDF5 refuses a null buffer).
    const bool empty = H5Sget_simple_extent_npoints(space) == 0;
    if (!ds.valid() ||
        (!empty && H5Dwrite(ds, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)) {
      throw Error("cannot write '" + path_ + "': HDF5 failed to write dataset " + name);
    }
  }

  // Groups on the way to name, created without modification times (same export, same bytes).
  void createParents(const std::string& name) {
    for (auto slash = name.find('/'); slash != std::string::npos;
         slash = name.find('/', slash + 1)) {
      const std::string group = name.substr(0, slash);
      if (H5Lexists(file_, group.c_str(), H5P_DEFAULT) > 0) continue;
      Handle g(H5Gcreate2(file_, group.c_str(), H5P_DEFAULT, gcpl_, H5P_DEFAULT), H5Gclose);
      if (!g.valid()) throw Error("cannot write '" + path_ + "': cannot create group " + group);
    }
  }

  static hid_t untimed(hid_t cls) {
    const hid_t plist = H5Pcreate(cls);
    H5Pset_obj_track_times(plist, 0);
    return plist;
  }

  hid_t file_;
  std::string path_;
  Handle lcpl_{H5Pcreate(H5P_LINK_CREATE), H5Pclose};
  Handle gcpl_{untimed(H5P_GROUP_CREATE), H5Pclose};
  Handle dcpl_{untimed(H5P_DATASET_CREATE), H5Pclose};
};

// ---------------------------------------------------------------- reading

// Foreign files carry no seal: they are read whole into memory (at most kMaxAcronymBytes)
// and every dataset may declare at most what its file could hold after deflate's best ratio.
constexpr std::size_t kMaxAcronymBytes = std::size_t{1} << 30;
constexpr hsize_t kMaxInflation = 1032;

class Reader {
 public:
  Reader(hid_t file, std::string path, std::size_t file_bytes)
      : file_(file), path_(std::move(path)), max_values_((file_bytes + 4096) * kMaxInflation / 8) {}

  bool has(const std::string& name) const {
    // Check every prefix so that a missing group is not an HDF5 error.
    std::size_t pos = 0;
    while (true) {
      pos = name.find('/', pos + 1);
      const std::string prefix = name.substr(0, pos);
      if (H5Lexists(file_, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
      if (pos == std::string::npos) return true;
    }
  }

  // Numeric dataset as doubles with its shape; any integer or float type.
  std::vector<double> doubles(const std::string& name, std::vector<hsize_t>* dims) const {
    Handle ds = open(name);
    Handle type(H5Dget_type(ds), H5Tclose);
    const H5T_class_t cls = H5Tget_class(type);
    if (cls != H5T_INTEGER && cls != H5T_FLOAT) fail(name, "is not numeric");
    Handle space(H5Dget_space(ds), H5Sclose);
    const int rank = H5Sget_simple_extent_ndims(space);
    if (rank < 0) fail(name, "has an unreadable shape");
    dims->assign(static_cast<std::size_t>(rank), 0);
    if (rank > 0) H5Sget_simple_extent_dims(space, dims->data(), nullptr);
    hsize_t count = 1;
    for (hsize_t d : *dims) {
      if (d != 0 && count > max_values_ / d) fail(name, "declares more values than the file holds");
      count *= d;
    }
    if (count > max_values_) fail(name, "declares more values than the file holds");
    std::vector<double> out(count);
    if (count > 0 &&
        H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0) {
      fail(name, "cannot be read as numbers");
    }
    return out;
  }

  double scalar(const std::string& name) const {
    std::vector<hsize_t> dims;
    const std::vector<double> v = doubles(name, &dims);
    if (v.size() != 1) fail(name, "should hold one number but holds " + std::to_string(v.size()));
    return v[0];
  }

  std::string string(const std::string& name) const {
    Handle ds = open(name);
    Handle type(H5Dget_type(ds), H5Tclose);
    if (H5Tget_class(type) != H5T_STRING) fail(name, "is not a string");
    Handle space(H5Dget_space(ds), H5Sclose);
    if (H5Sget_simple_extent_npoints(space) != 1) fail(name, "should hold one string");
    if (H5Tis_variable_str(type) > 0) {
      Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
      H5Tset_size(mem, H5T_VARIABLE);
      H5Tset_cset(mem, H5Tget_cset(type));
      char* ptr = nullptr;
      if (H5Dread(ds, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, &ptr) < 0) fail(name, "cannot be read");
      std::string out = ptr ? ptr : "";
      H5Dvlen_reclaim(mem, space, H5P_DEFAULT, &ptr);
      return out;
    }
    const std::size_t size = H5Tget_size(type);
    if (size > (std::size_t{1} << 20)) fail(name, "declares a string longer than 1 MiB");
    std::string buf(size, '\0');
    Handle mem(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(mem, size);
    if (size > 0 && H5Dread(ds, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()) < 0) {
      fail(name, "cannot be read");
    }
    buf.resize(std::strlen(buf.c_str()));
    return buf;
  }

  [[noreturn]] void fail(const std::string& name, const std::string& what) const {
    throw Error("'" + path_ + "': dataset " + name + " " + what +
                "; is this an ACRONYM grasp file?");
  }

 private:
  Handle open(const std::string& name) const {
    if (!has(name)) fail(name, "is missing");
    Handle ds(H5Dopen2(file_, name.c_str(), H5P_DEFAULT), H5Dclose);
    if (!ds.valid()) fail(name, "cannot be opened (is it a group?)");
    return ds;
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
  const double volume = map.object.volume;
  const Eigen::Matrix3d inertia = meshInertia(map.object.vertices, map.object.faces,
                                              map.object.center_of_mass, options.density);
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> inertia_rm = inertia;
  const std::string object_file =
      options.object_file.empty() ? map.object.name + ".obj" : options.object_file;

  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  {
    std::lock_guard<std::mutex> lock(h5::hdf5Mutex());
    h5::silenceErrors();
    const h5::Id fcpl = h5::mapFileCreation(0);  // no user block; no root-group times
    Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, fcpl, H5P_DEFAULT), H5Fclose);
    if (!file.valid()) {
      throw Error("cannot write '" + path + "': cannot create '" + tmp +
                  "'; check that the directory exists and is writable");
    }
    try {
      Writer w(file, path);
      w.doubles("grasps/transforms", {n, 4, 4}, transforms.data());
      w.int64s("grasps/qualities/flex/object_in_gripper", success);
      w.doubles("grasps/qualities/taskmap/epsilon", {n}, g.epsilon.data());
      w.string("object/file", object_file);
      w.scalar("object/scale", map.object.scale);
      w.scalar("object/density", options.density);
      w.scalar("object/mass", options.density * volume);
      w.scalar("object/friction", map.quality.friction);
      w.scalar("object/volume", volume);
      w.doubles("object/com", {3}, map.object.center_of_mass.data());
      w.doubles("object/inertia", {3, 3}, inertia_rm.data());
      w.string("gripper/type", map.hand.name);
      w.doubles("gripper/configuration", {0}, nullptr);
      Eigen::Matrix<double, 4, 4, Eigen::RowMajor> b = options.base_to_palm.matrix();
      w.doubles("gripper/taskmap_base_to_palm", {4, 4}, b.data());
      if (!file.close()) throw Error("cannot write '" + path + "': HDF5 failed to close the file");
    } catch (...) {
      file.close();
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw;
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
