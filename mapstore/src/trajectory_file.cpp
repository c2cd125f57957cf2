// Reaching trajectory files: sealed HDF5, layout in mapstore/TRAJECTORY.md. The seal and the
// HDF5 helpers are the task map file's (map_seal.hpp, hdf5_io.hpp).
#include "taskmap/mapstore/trajectory_file.hpp"

#include <unistd.h>

#include <atomic>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>

#include "hdf5_io.hpp"
#include "map_seal.hpp"
#include "taskmap/core/atomic_file.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

using h5::Id;

constexpr const char* kFormat = "taskmap-trajectory";
constexpr int kShapeColumns = 15;  // center 3, axes 9 (column-major u v n), half_u, half_v, r

std::string rowsText(std::size_t n) {
  return std::to_string(n);
}

void requireRows(const RowMatrixXd& m, std::size_t rows, Eigen::Index cols,
                 const std::string& name) {
  if (static_cast<std::size_t>(m.rows()) != rows || m.cols() != cols)
    throw Error(name + " is " + rowsText(m.rows()) + " x " + rowsText(m.cols()) + ", expected " +
                rowsText(rows) + " x " + rowsText(cols));
  if (!m.allFinite()) throw Error(name + " holds a non-finite value");
}

void requirePoses(const RowMatrixXd& m, const std::string& name) {
  for (Eigen::Index r = 0; r < m.rows(); ++r)
    for (Eigen::Index c = 0; c + 7 <= m.cols(); c += 7) {
      const double n = m.row(r).segment<4>(c + 3).norm();
      if (std::abs(n - 1.0) > 1e-6)
        throw Error(name + " row " + rowsText(r) + " column " + rowsText(c + 3) +
                    ": quaternion norm " + std::to_string(n) + " is not 1");
    }
}

RowMatrixXd toRows(const h5::Array<double>& a, std::size_t cols) {
  RowMatrixXd m(static_cast<Eigen::Index>(a.rows()), static_cast<Eigen::Index>(cols));
  std::copy(a.values.begin(), a.values.end(), m.data());
  return m;
}

std::vector<std::int32_t> toInt32(const h5::Array<std::int64_t>& a, const std::string& name) {
  std::vector<std::int32_t> out;
  for (std::size_t i = 0; i < a.values.size(); ++i) {
    if (a.values[i] < std::numeric_limits<std::int32_t>::min() ||
        a.values[i] > std::numeric_limits<std::int32_t>::max())
      throw Error(name + ": entry " + rowsText(i) + " is out of range");
    out.push_back(static_cast<std::int32_t>(a.values[i]));
  }
  return out;
}

// ---------------------------------------------------------------- writing

void writeShapes(hid_t file, const TrajectoryRecord& r) {
  const std::size_t n = r.shapes.size();
  std::vector<std::int32_t> body(n), type(n);
  RowMatrixXd params(static_cast<Eigen::Index>(n), kShapeColumns);
  for (std::size_t i = 0; i < n; ++i) {
    const TrajectoryShape& s = r.shapes[i];
    const auto row = static_cast<Eigen::Index>(i);
    body[i] = s.body;
    type[i] = static_cast<std::int32_t>(s.type);
    params.row(row).head<3>() = s.center.transpose();
    params.row(row).segment<9>(3) = Eigen::Map<const Eigen::Matrix<double, 1, 9>>(s.axes.data());
    params.row(row).tail<3>() << s.half_u, s.half_v, s.radius;
  }
  Id g = h5::createGroup(file, "shapes");
  h5::writeVector(g, "body", h5::Type::kI32, body.data(), n);
  h5::writeVector(g, "type", h5::Type::kI32, type.data(), n);
  h5::writeDataset(g, "params", h5::Type::kF64, params.data(), n, kShapeColumns);
}

/// /plan/grasp: the map's hand and the chosen grasp's joint values (only when known).
void writeGrasp(hid_t plan, const TrajectoryRecord& r) {
  Id g = h5::createGroup(plan, "grasp");
  h5::writeAttr(g, "hand", r.map_hand);
  h5::writeAttr(g, "hand_sha256", r.map_hand_sha256);
  h5::writeAttr(g, "hand_path", r.map_hand_path);
  h5::writeStrings(g, "joint_names", r.grasp_joint_names);
  h5::writeVector(g, "joints", h5::Type::kF64, r.grasp_joints.data(),
                  static_cast<std::size_t>(r.grasp_joints.size()));
}

void writeGroups(hid_t file, const TrajectoryRecord& r) {
  const std::size_t s = r.rows(), d = r.joint_names.size(), b = r.body_names.size();
  {
    Id g = h5::createGroup(file, "robot");
    h5::writeAttr(g, "robot", r.robot);
    h5::writeAttr(g, "hand", r.hand);
    h5::writeAttr(g, "dt_s", r.dt);
    h5::writeStrings(g, "joint_names", r.joint_names);
    h5::writeDataset(g, "joints", h5::Type::kF64, r.joints.data(), s, d);
    h5::writeDataset(g, "palm_world", h5::Type::kF64, r.palm_world.data(), s, 7);
    h5::writeDataset(g, "palm_object", h5::Type::kF64, r.palm_object.data(), s, 7);
  }
  {
    Id g = h5::createGroup(file, "object");
    h5::writeAttr(g, "name", r.object_name);
    const Eigen::Matrix<double, 7, 1> pose = r.object_pose.toVector7();
    h5::writeAttrVector(g, "pose", pose.data(), 7);
    h5::writeDataset(g, "vertices", h5::Type::kF64, r.object_vertices.data(),
                     static_cast<std::size_t>(r.object_vertices.rows()), 3);
    h5::writeDataset(g, "faces", h5::Type::kI64, r.object_faces.data(),
                     static_cast<std::size_t>(r.object_faces.rows()), 3);
  }
  {
    Id g = h5::createGroup(file, "plan");
    h5::writeAttr(g, "map_path", r.map_path);
    h5::writeAttr(g, "map_sha256", r.map_sha256);
    h5::writeAttrInt(g, "start_cluster", r.start_cluster);
    h5::writeAttrInt(g, "cluster", r.cluster);
    h5::writeAttrInt(g, "grasp_index", r.grasp_index);
    if (r.quality_peak != 1.0) h5::writeAttr(g, "quality_peak", r.quality_peak);  // else as before
    h5::writeStrings(g, "cost_terms", r.cost_terms);
    h5::writeDataset(g, "cost_history", h5::Type::kF64, r.cost_history.data(),
                     static_cast<std::size_t>(r.cost_history.rows()), r.cost_terms.size());
    h5::writeVector(g, "proximity_over_movement", h5::Type::kF64, r.proximity_over_movement.data(),
                    s);
    h5::writeVector(g, "quality_over_movement", h5::Type::kF64, r.quality_over_movement.data(), s);
    if (!r.grasp_joint_names.empty()) writeGrasp(g, r);
  }
  Id g = h5::createGroup(file, "bodies");
  h5::writeStrings(g, "names", r.body_names);
  h5::writeVector(g, "parent", h5::Type::kI32, r.body_parents.data(), b);
  h5::writeVector(g, "role", h5::Type::kI32, r.body_roles.data(), b);
  h5::writeDataset(g, "poses", h5::Type::kF64, r.body_poses.data(), s, 7 * b);
}

void writeFile(const std::string& tmp, const TrajectoryRecord& r) {
  Id fcpl = h5::mapFileCreation(seal::kSealBytes);
  Id fapl = h5::mapFileAccess();
  Id file = h5::checked(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, fcpl, fapl), H5Fclose,
                        "cannot create file (directory missing or not writable?)");
  h5::writeAttr(file, "format", std::string(kFormat));
  h5::writeAttrInt(file, "schema_version", kTrajectorySchemaVersion);
  h5::writeAttr(file, "generator", r.generator);
  h5::writeAttr(file, "created_utc", r.created_utc);
  writeGroups(file, r);
  writeShapes(file, r);
  h5::check(H5Fflush(file, H5F_SCOPE_GLOBAL), "cannot flush the file (disk full?)");
  if (!file.reset()) throw Error("cannot close the file (disk full?)");
  seal::stampFile(tmp);
}

// ---------------------------------------------------------------- reading

void readRobot(hid_t file, TrajectoryRecord& r) {
  Id g = h5::openGroup(file, "/robot");
  r.robot = h5::readAttrString(g, "/robot", "robot");
  r.hand = h5::readAttrString(g, "/robot", "hand");
  r.dt = h5::readAttrDouble(g, "/robot", "dt_s");
  r.joint_names = h5::readStrings(file, "/robot/joint_names");
  r.joints =
      toRows(h5::readF64(file, "/robot/joints", 2, r.joint_names.size()), r.joint_names.size());
  r.palm_world = toRows(h5::readF64(file, "/robot/palm_world", 2, 7), 7);
  r.palm_object = toRows(h5::readF64(file, "/robot/palm_object", 2, 7), 7);
}

void readObject(hid_t file, TrajectoryRecord& r) {
  Id g = h5::openGroup(file, "/object");
  r.object_name = h5::readAttrString(g, "/object", "name");
  const std::vector<double> pose = h5::readAttrVector(g, "/object", "pose", 7);
  const Eigen::Matrix<double, 7, 1> v(pose.data());
  if (!v.allFinite() || std::abs(v.tail<4>().norm() - 1.0) > 1e-6)
    throw Error("/object attribute pose is not a finite pose with a unit quaternion");
  r.object_pose = Pose::fromVector7(v);
  r.object_vertices = toRows(h5::readF64(file, "/object/vertices", 2, 3), 3);
  const auto faces = h5::readI64(file, "/object/faces", 2, 3);
  r.object_faces.resize(static_cast<Eigen::Index>(faces.rows()), 3);
  std::copy(faces.values.begin(), faces.values.end(), r.object_faces.data());
}

void readPlan(hid_t file, TrajectoryRecord& r) {
  Id g = h5::openGroup(file, "/plan");
  r.map_path = h5::readAttrString(g, "/plan", "map_path");
  r.map_sha256 = h5::readAttrString(g, "/plan", "map_sha256");
  const std::int64_t start = h5::readAttrInt(g, "/plan", "start_cluster");
  const std::int64_t cluster = h5::readAttrInt(g, "/plan", "cluster");
  if (start < -1 || start > std::numeric_limits<int>::max() || cluster < -1 ||
      cluster > std::numeric_limits<int>::max())
    throw Error("/plan attributes start_cluster/cluster are out of range");
  r.start_cluster = static_cast<int>(start);
  r.cluster = static_cast<int>(cluster);
  r.grasp_index = h5::readAttrInt(g, "/plan", "grasp_index");
  // Written before the quality term was scaled: its quality columns are the raw g_q.
  r.quality_peak =
      h5::hasAttr(g, "quality_peak") ? h5::readAttrDouble(g, "/plan", "quality_peak") : 1.0;
  r.cost_terms = h5::readStrings(file, "/plan/cost_terms");
  r.cost_history =
      toRows(h5::readF64(file, "/plan/cost_history", 2, r.cost_terms.size()), r.cost_terms.size());
  const auto p = h5::readF64(file, "/plan/proximity_over_movement", 1);
  const auto q = h5::readF64(file, "/plan/quality_over_movement", 1);
  r.proximity_over_movement =
      Eigen::Map<const Eigen::VectorXd>(p.values.data(), static_cast<Eigen::Index>(p.rows()));
  r.quality_over_movement =
      Eigen::Map<const Eigen::VectorXd>(q.values.data(), static_cast<Eigen::Index>(q.rows()));
  if (!h5::exists(g, "grasp")) return;  // written before the grasp was recorded
  Id grasp = h5::openGroup(file, "/plan/grasp");
  r.map_hand = h5::readAttrString(grasp, "/plan/grasp", "hand");
  r.map_hand_sha256 = h5::readAttrString(grasp, "/plan/grasp", "hand_sha256");
  r.map_hand_path = h5::readAttrString(grasp, "/plan/grasp", "hand_path");
  r.grasp_joint_names = h5::readStrings(file, "/plan/grasp/joint_names");
  const auto j = h5::readF64(file, "/plan/grasp/joints", 1);
  r.grasp_joints =
      Eigen::Map<const Eigen::VectorXd>(j.values.data(), static_cast<Eigen::Index>(j.rows()));
}

void readBodies(hid_t file, TrajectoryRecord& r) {
  r.body_names = h5::readStrings(file, "/bodies/names");
  r.body_parents = toInt32(h5::readI64(file, "/bodies/parent", 1), "/bodies/parent");
  r.body_roles = toInt32(h5::readI64(file, "/bodies/role", 1), "/bodies/role");
  r.body_poses = toRows(h5::readF64(file, "/bodies/poses", 2, 7 * r.body_names.size()),
                        7 * r.body_names.size());
  const auto body = toInt32(h5::readI64(file, "/shapes/body", 1), "/shapes/body");
  const auto type = toInt32(h5::readI64(file, "/shapes/type", 1), "/shapes/type");
  const RowMatrixXd params =
      toRows(h5::readF64(file, "/shapes/params", 2, kShapeColumns), kShapeColumns);
  if (type.size() != body.size() || static_cast<std::size_t>(params.rows()) != body.size())
    throw Error("/shapes: body, type and params differ in length");
  r.shapes.resize(body.size());
  for (std::size_t i = 0; i < body.size(); ++i) {
    TrajectoryShape& s = r.shapes[i];
    const auto row = static_cast<Eigen::Index>(i);
    if (type[i] != 0 && type[i] != 1)
      throw Error("/shapes/type: entry " + rowsText(i) + " is neither 0 nor 1");
    s.body = body[i];
    s.type = static_cast<TrajectoryShapeType>(type[i]);
    s.center = params.row(row).head<3>().transpose();
    s.axes = Eigen::Map<const Eigen::Matrix3d>(params.row(row).segment<9>(3).eval().data());
    s.half_u = params(row, 12);
    s.half_v = params(row, 13);
    s.radius = params(row, 14);
  }
}

TrajectoryRecord readFile(hid_t file) {
  if (!h5::hasAttr(file, "format") ||
      h5::readAttrString(file, "/", "format") != std::string(kFormat))
    throw Error("not a trajectory file (root attribute format is not \"" + std::string(kFormat) +
                "\"; a task map? those are read by --map)");
  const std::int64_t version = h5::readAttrInt(file, "/", "schema_version");
  if (version > kTrajectorySchemaVersion)
    throw Error("written by a newer taskmap (trajectory schema " + std::to_string(version) +
                "); upgrade taskmap to read it");
  if (version < 1) throw Error("invalid schema_version " + std::to_string(version));
  TrajectoryRecord r;
  r.generator = h5::readAttrString(file, "/", "generator");
  r.created_utc = h5::readAttrString(file, "/", "created_utc");
  readRobot(file, r);
  readObject(file, r);
  readPlan(file, r);
  readBodies(file, r);
  r.validate();
  return r;
}

std::string tempPathFor(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
}

void validateShapes(const TrajectoryRecord& r) {
  for (std::size_t i = 0; i < r.shapes.size(); ++i) {
    const TrajectoryShape& s = r.shapes[i];
    const std::string name = "shape " + rowsText(i);
    if (s.body < 0 || static_cast<std::size_t>(s.body) >= r.body_names.size())
      throw Error(name + ": body " + std::to_string(s.body) + " is not a body index");
    if (!s.center.allFinite() || !s.axes.allFinite() || !(s.half_u >= 0) || !(s.half_v >= 0) ||
        !(s.radius >= 0) || !std::isfinite(s.half_u + s.half_v + s.radius))
      throw Error(name + ": sizes must be finite and >= 0, centre and axes finite");
    if (!(s.axes.transpose() * s.axes).isIdentity(1e-6))
      throw Error(name + ": axes are not orthonormal");
  }
}

}  // namespace

Pose TrajectoryRecord::bodyPose(std::size_t t, std::size_t b) const {
  assert(t < rows() && b < body_names.size());
  return Pose::fromVector7(body_poses.row(static_cast<Eigen::Index>(t))
                               .segment<7>(static_cast<Eigen::Index>(7 * b))
                               .transpose());
}

void TrajectoryRecord::validate() const {
  const std::size_t s = rows(), d = joint_names.size(), b = body_names.size();
  if (s < 1) throw Error("the trajectory has no steps");
  if (!(dt > 0.0) || !std::isfinite(dt)) throw Error("dt_s must be finite and > 0");
  requireRows(joints, s, static_cast<Eigen::Index>(d), "joints");
  requireRows(palm_world, s, 7, "palm_world");
  requireRows(palm_object, s, 7, "palm_object");
  requirePoses(palm_world, "palm_world");
  requirePoses(palm_object, "palm_object");
  requireRows(object_vertices, static_cast<std::size_t>(object_vertices.rows()), 3,
              "object vertices");
  if ((object_faces.array() < 0).any() || (object_faces.array() >= object_vertices.rows()).any())
    throw Error("object faces index a vertex outside [0, " + rowsText(object_vertices.rows()) +
                ")");
  if (!(quality_peak > 0.0) || !std::isfinite(quality_peak))
    throw Error("quality_peak must be finite and > 0, not " + std::to_string(quality_peak));
  requireRows(cost_history, static_cast<std::size_t>(cost_history.rows()),
              static_cast<Eigen::Index>(cost_terms.size()), "cost_history");
  if (static_cast<std::size_t>(proximity_over_movement.size()) != s ||
      static_cast<std::size_t>(quality_over_movement.size()) != s)
    throw Error("proximity/quality_over_movement need one value per step (" + rowsText(s) + ")");
  if (static_cast<std::size_t>(grasp_joints.size()) != grasp_joint_names.size() ||
      !grasp_joints.allFinite())
    throw Error("grasp joints need one finite value per grasp joint name (" +
                rowsText(grasp_joint_names.size()) + ")");
  if (body_parents.size() != b || body_roles.size() != b)
    throw Error("body parents and roles need one entry per body (" + rowsText(b) + ")");
  for (std::size_t i = 0; i < b; ++i) {
    if (body_parents[i] < -1 || body_parents[i] >= static_cast<std::int32_t>(i))
      throw Error("body " + body_names[i] + ": parent must be -1 or an earlier body");
    if (body_roles[i] < 0 || body_roles[i] > 2)
      throw Error("body " + body_names[i] + ": role must be 0, 1 or 2");
  }
  requireRows(body_poses, s, static_cast<Eigen::Index>(7 * b), "body poses");
  requirePoses(body_poses, "body poses");
  validateShapes(*this);
}

void writeTrajectory(const std::string& path, const TrajectoryRecord& record) {
  try {
    record.validate();
  } catch (const Error& e) {
    throw Error("refusing to write invalid trajectory '" + path + "': " + e.what());
  }
  const std::string tmp = tempPathFor(path);
  std::lock_guard<std::mutex> lock(h5::hdf5Mutex());
  h5::silenceErrors();
  try {
    writeFile(tmp, record);
  } catch (const Error& e) {
    std::remove(tmp.c_str());
    throw Error("cannot write trajectory '" + path + "': " + e.what());
  }
  commitTemporaryFile(tmp, path, "cannot write trajectory '" + path + "'");
}

TrajectoryRecord readTrajectory(const std::string& path) {
  try {
    const std::string bytes = seal::readVerified(
        path, "trajectory file", "; write it again with `taskmap reach --map ... -o FILE`");
    std::lock_guard<std::mutex> lock(h5::hdf5Mutex());
    h5::silenceErrors();
    Id file = h5::openImage(bytes, "cannot open the sealed content as HDF5");
    return readFile(file);
  } catch (const Error& e) {
    throw Error("trajectory '" + path + "': " + e.what());
  }
}

}  // namespace taskmap
