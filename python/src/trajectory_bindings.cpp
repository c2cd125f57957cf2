// taskmap.read_trajectory: a trajectory file (`taskmap reach --map ... -o`) read through the
// verified reader (seal checked before HDF5 parses a byte), as a dict of numpy arrays.
#include "trajectory_bindings.hpp"

#include "core_docs.hpp"

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "taskmap/mapstore/trajectory_file.hpp"

namespace py = pybind11;

namespace taskmap {
namespace {

/// S x B x 7 body poses from the stored S x 7B rows.
py::array_t<double> bodyPoses(const TrajectoryRecord& r) {
  const auto s = static_cast<py::ssize_t>(r.rows());
  const auto b = static_cast<py::ssize_t>(r.body_names.size());
  py::array_t<double> a({s, b, py::ssize_t{7}});
  std::copy(r.body_poses.data(), r.body_poses.data() + r.body_poses.size(), a.mutable_data());
  return a;
}

py::dict shapesDict(const TrajectoryRecord& r) {
  std::vector<int> body, type;
  Eigen::MatrixXd params(static_cast<Eigen::Index>(r.shapes.size()), 15);
  for (std::size_t i = 0; i < r.shapes.size(); ++i) {
    const TrajectoryShape& s = r.shapes[i];
    body.push_back(s.body);
    type.push_back(static_cast<int>(s.type));
    params.row(static_cast<Eigen::Index>(i)) << s.center.transpose(),
        Eigen::Map<const Eigen::Matrix<double, 1, 9>>(s.axes.data()), s.half_u, s.half_v, s.radius;
  }
  py::dict d;
  d["body"] = body;
  d["type"] = type;
  d["params"] = params;
  return d;
}

py::dict trajectoryDict(const TrajectoryRecord& r) {
  py::dict d;
  d["generator"] = r.generator;
  d["created_utc"] = r.created_utc;
  d["robot"] = r.robot;
  d["hand"] = r.hand;
  d["dt"] = r.dt;
  d["joint_names"] = r.joint_names;
  d["joints"] = Eigen::MatrixXd(r.joints);
  d["palm_world"] = Eigen::MatrixXd(r.palm_world);
  d["palm_object"] = Eigen::MatrixXd(r.palm_object);
  d["object_name"] = r.object_name;
  d["object_pose"] = Eigen::VectorXd(r.object_pose.toVector7());
  d["object_vertices"] = Eigen::MatrixXd(r.object_vertices);
  d["object_faces"] = Eigen::Matrix<std::int64_t, Eigen::Dynamic, 3>(r.object_faces);
  d["map_path"] = r.map_path;
  d["map_sha256"] = r.map_sha256;
  d["start_cluster"] = r.start_cluster;
  d["cluster"] = r.cluster;
  d["grasp_index"] = r.grasp_index;
  d["quality_peak"] = r.quality_peak;
  d["map_hand"] = r.map_hand;
  d["map_hand_sha256"] = r.map_hand_sha256;
  d["map_hand_path"] = r.map_hand_path;
  d["grasp_joint_names"] = r.grasp_joint_names;
  d["grasp_joints"] = r.grasp_joints;
  d["cost_terms"] = r.cost_terms;
  d["cost_history"] = Eigen::MatrixXd(r.cost_history);
  d["proximity_over_movement"] = r.proximity_over_movement;
  d["quality_over_movement"] = r.quality_over_movement;
  d["body_names"] = r.body_names;
  d["body_parents"] = r.body_parents;
  d["body_roles"] = r.body_roles;
  d["body_poses"] = bodyPoses(r);
  d["shapes"] = shapesDict(r);
  return d;
}

}  // namespace

void bindTrajectory(py::module_& m) {
  m.def(
      "read_trajectory",
      [](const std::string& path) { return trajectoryDict(readTrajectory(path)); }, py::arg("path"),
      pydoc::kReadTrajectory);
}

}  // namespace taskmap
