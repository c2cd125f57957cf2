// taskmap._core: the run-time query library (integration, mapstore, clustering), what
// `import taskmap` loads. No simulator, mesh or URDF library is linked here: the offline stages
// are in taskmap._offline (offline_module.cpp), loaded on first use.
// Poses are numpy arrays (x y z qw qx qy qz), gradients 6-vectors (linear, angular) in the
// object frame; taskmap::Error becomes taskmap.Error, a subclass of ValueError.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <type_traits>

#include "core_docs.hpp"
#include "map_arrays.hpp"
#include "trajectory_bindings.hpp"

#include "taskmap/clustering/clustering.hpp"
#include "taskmap/core/data_dir.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/integration/criteria.hpp"
#include "taskmap/integration/evaluation_session.hpp"
#include "taskmap/integration/frames.hpp"
#include "taskmap/integration/initialisation.hpp"
#include "taskmap/integration/task_map.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace py = pybind11;
using namespace taskmap;

namespace {

using Vec7 = Eigen::Matrix<double, 7, 1>;

Pose toPose(const Vec7& v) {
  return Pose::fromVector7(v);
}
Vec7 fromPose(const Pose& p) {
  return p.toVector7();
}

TaskMapOptions makeOptions(const py::kwargs& kw) {
  TaskMapOptions o;
  for (const auto& item : kw) {
    const std::string k = py::str(item.first);
    const py::handle v = item.second;
    if (k == "index") {
      const std::string s = py::str(v);
      if (s == "exact")
        o.index = IndexKind::kExactKdTree;
      else if (s == "randomized")
        o.index = IndexKind::kRandomizedForest;
      else
        throw Error("option index = '" + s + "'; use 'exact' or 'randomized'");
    } else if (k == "trees") {
      o.trees = v.cast<int>();
    } else if (k == "checks") {
      o.checks = v.cast<int>();
    } else if (k == "linear_weight") {
      o.linear_weight = v.cast<double>();
    } else if (k == "angular_weight") {
      o.angular_weight = v.cast<double>();
    } else if (k == "position_sigma") {
      o.position_sigma = v.cast<double>();
    } else if (k == "rotation_sigma") {
      o.rotation_sigma = v.cast<double>();
    } else if (k == "bandwidth_factor") {
      o.bandwidth_factor = v.cast<double>();
    } else if (k == "quality_mode") {
      const std::string s = py::str(v);
      if (s == "exact")
        o.quality_mode = QualityMode::kExact;
      else if (s == "truncated")
        o.quality_mode = QualityMode::kTruncated;
      else
        throw Error("option quality_mode = '" + s + "'; use 'exact' or 'truncated'");
    } else if (k == "quality_tolerance") {
      o.quality_tolerance = v.cast<double>();
    } else if (k == "sample_weight") {
      o.sample_weight = sampleWeightFromString(py::str(v));
    } else if (k == "threads") {
      o.threads = v.cast<int>();
    } else {
      throw Error("unknown option '" + k +
                  "'; known: index, trees, checks, linear_weight, angular_weight, "
                  "position_sigma, rotation_sigma, bandwidth_factor, quality_mode, "
                  "quality_tolerance, sample_weight, threads");
    }
  }
  return o;
}

std::optional<QualityMode> modeOf(const std::optional<std::string>& s) {
  if (!s) return std::nullopt;
  if (*s == "exact") return QualityMode::kExact;
  if (*s == "truncated") return QualityMode::kTruncated;
  throw Error("quality mode '" + *s + "'; use 'exact' or 'truncated'");
}

py::tuple neighbours(const std::vector<Neighbor>& v) {
  Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> idx(static_cast<Eigen::Index>(v.size()));
  Eigen::VectorXd d(static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) {
    idx[static_cast<Eigen::Index>(i)] = static_cast<std::int64_t>(v[i].index);
    d[static_cast<Eigen::Index>(i)] = v[i].distance;
  }
  return py::make_tuple(idx, d);
}

py::dict qualityDict(const QualityCriterion& q) {
  py::dict d;
  d["value"] = q.value;
  d["gradient"] = Eigen::VectorXd(q.gradient);
  d["value_bound"] = q.value_bound;
  d["gradient_bound"] = q.gradient_bound;
  d["terms"] = q.terms;
  return d;
}

// The dict of TaskMap.evaluate and Session.evaluate.
py::dict evaluationDict(const Evaluation& e) {
  py::dict d;
  d["cost"] = e.cost();
  d["gradient"] = Eigen::VectorXd(e.gradient());
  d["proximity"] = e.proximity.value;
  d["proximity_gradient"] = Eigen::VectorXd(e.proximity.gradient);
  d["quality"] = e.quality.value;
  d["quality_gradient"] = Eigen::VectorXd(e.quality.gradient);
  d["quality_bound"] = e.quality.value_bound;
  d["nearest"] = e.proximity.nearest.index;
  d["nearest_distance"] = e.proximity.nearest.distance;
  return d;
}

py::dict proximityDict(const ProximityResult& p) {
  py::dict d;
  d["value"] = p.value;
  d["gradient"] = Eigen::VectorXd(p.gradient);
  d["nearest"] = p.nearest.index;
  d["distance"] = p.nearest.distance;
  d["difference"] = Eigen::VectorXd(p.difference);
  return d;
}

TaskMap fromArrays(const PoseRows& poses, const std::vector<double>& epsilon,
                   const std::optional<std::vector<int>>& labels, double rotation_scale,
                   const py::kwargs& kw) {
  TaskMapData d;
  const std::size_t n = static_cast<std::size_t>(poses.rows());
  d.generator = "taskmap python from_arrays";
  d.grasps.pose = poses;
  for (std::size_t i = 0; i < n; ++i) {  // canonical, normalised quaternions
    const Pose p = Pose::fromVector7(poses.row(static_cast<Eigen::Index>(i)).transpose());
    d.grasps.pose.row(static_cast<Eigen::Index>(i)) = p.toVector7().transpose();
  }
  d.grasps.epsilon = epsilon;
  d.grasps.rotation_scale = rotation_scale;
  d.grasps.joints.resize(static_cast<Eigen::Index>(n), 0);
  d.grasps.volume.assign(n, 0.0);
  d.grasps.contact_offsets.assign(n + 1, 0);
  d.grasps.contacts_available = false;
  d.grasps.contact_points.resize(0, 3);
  d.grasps.contact_normals.resize(0, 3);
  d.object.name = "from_arrays";
  d.object.vertices.resize(0, 3);
  d.grasps.force_closure.resize(n);
  for (std::size_t i = 0; i < std::min(n, epsilon.size()); ++i)
    d.grasps.force_closure[i] = epsilon[i] > 0 ? 1 : 0;
  if (labels) {
    if (labels->size() != n)
      throw Error("labels has " + std::to_string(labels->size()) + " entries; expected " +
                  std::to_string(n) + " (one per pose)");
    ClusteringResult c;
    c.labels = *labels;
    c.rotation_scale = rotation_scale;
    const int k = labels->empty() ? 0 : *std::max_element(labels->begin(), labels->end()) + 1;
    c.clusters.resize(static_cast<std::size_t>(std::max(0, k)));
    std::vector<std::vector<Eigen::Quaterniond>> qs(c.clusters.size());
    for (std::size_t i = 0; i < n; ++i) {
      const int l = (*labels)[i];
      if (l < -1)
        throw Error("labels[" + std::to_string(i) + "] = " + std::to_string(l) +
                    "; use -1 (outlier) or 0..K-1");
      if (l < 0) continue;
      ClusterSummary& s = c.clusters[static_cast<std::size_t>(l)];
      const Pose p = d.grasps.poseAt(i);
      const double e = i < epsilon.size() ? epsilon[i] : 0.0;
      if (s.size == 0) {
        s.bounds_min = s.bounds_max = p.position;
        s.representative = static_cast<int>(i);
        s.best_epsilon = e;
      }
      s.bounds_min = s.bounds_min.cwiseMin(p.position);
      s.bounds_max = s.bounds_max.cwiseMax(p.position);
      if (e > s.best_epsilon) {
        s.best_epsilon = e;
        s.representative = static_cast<int>(i);
      }
      s.mean_pose.position += p.position;
      s.mean_epsilon += e;
      qs[static_cast<std::size_t>(l)].push_back(p.orientation);
      ++s.size;
    }
    for (std::size_t j = 0; j < c.clusters.size(); ++j) {
      ClusterSummary& s = c.clusters[j];
      if (s.size == 0)
        throw Error("labels: cluster " + std::to_string(j) +
                    " has no grasps; labels must be 0..K-1 without gaps");
      s.mean_pose.position /= s.size;
      s.mean_epsilon /= s.size;
      s.mean_pose.orientation = meanOrientation(qs[j]);
    }
    if (n >= 2) {
      PointMatrix pts(static_cast<Eigen::Index>(n), kEmbeddingDim);
      for (std::size_t i = 0; i < n; ++i)
        pts.row(static_cast<Eigen::Index>(i)) =
            embedPose(d.grasps.poseAt(i), rotation_scale).transpose();
      c.linkage = computeLinkage(pts, Linkage::kSingle);
    }
    d.clustering = c;
  }
  return TaskMap::fromData(std::move(d), makeOptions(kw));
}

void bindTaskMapQueries(py::class_<TaskMap>& cls);
void bindClusterRanking(py::class_<TaskMap>& cls);

/// taskmap.TaskMap: load, save, from_arrays, the stored arrays, then the queries.
void bindTaskMap(py::module_& m) {
  py::class_<TaskMap> cls(m, "TaskMap", pydoc::kTaskMap);
  cls.def_static(
         "load",
         [](const std::string& path, const py::kwargs& kw) {
           return TaskMap::load(path, makeOptions(kw));
         },
         py::arg("path"), pydoc::kLoad)
      .def_static("from_arrays", &fromArrays, py::arg("poses"), py::arg("epsilon"),
                  py::arg("labels") = py::none(), py::arg("rotation_scale") = kDefaultRotationScale,
                  pydoc::kFromArrays)
      .def(
          "save", [](const TaskMap& t, const std::string& path) { writeMap(path, t.data()); },
          py::arg("path"), pydoc::kSave)
      .def("__len__", &TaskMap::size)
      .def_property_readonly("size", &TaskMap::size, "Number of grasps N (also len(map)).")
      .def_property_readonly("num_clusters", &TaskMap::numClusters,
                             "Number of clusters K (0 for an unclustered map).")
      .def_property_readonly("rotation_scale", &TaskMap::rotationScale,
                             "rho of the pose metric, metres per radian.")
      .def_property_readonly(
          "position_sigma", [](const TaskMap& t) { return *t.options().position_sigma; },
          "sigma_p of the quality kernels, metres.")
      .def_property_readonly(
          "rotation_sigma", [](const TaskMap& t) { return *t.options().rotation_sigma; },
          "sigma_r of the quality kernels, radians.")
      .def_property_readonly(
          "linear_weight", [](const TaskMap& t) { return t.options().linear_weight; },
          "w_p of the proximity criterion, 1/m^2.")
      .def_property_readonly(
          "angular_weight", [](const TaskMap& t) { return *t.options().angular_weight; },
          "w_r of the proximity criterion, 1/rad^2.")
      .def_property_readonly(
          "sample_weight", [](const TaskMap& t) { return toString(t.options().sample_weight); },
          "What weighs each sample in the quality criterion: 'epsilon' or 'hold_margin' (epsilon "
          "x the physics hold margin; the default when the map is fully validated)")
      .def_property_readonly("cutoff_radius", &TaskMap::cutoffRadius,
                             "Radius (pose metric, metres) within which the truncated quality "
                             "sums the grasps.")
      .def_property_readonly(
          "poses", [](const TaskMap& t) { return t.data().grasps.pose; },
          "N x 7 palm poses [x y z qw qx qy qz] in the object frame (metres).")
      .def_property_readonly(
          "epsilon",
          [](const TaskMap& t) {
            const auto& e = t.data().grasps.epsilon;
            return py::array_t<double>(static_cast<py::ssize_t>(e.size()), e.data());
          },
          "N epsilon qualities (numpy array).")
      .def_property_readonly(
          "labels",
          [](const TaskMap& t) -> py::object {
            if (!t.data().clustering) return py::none();
            const auto& l = t.data().clustering->labels;
            using Label = std::decay_t<decltype(l[0])>;
            return py::array_t<Label>(static_cast<py::ssize_t>(l.size()), l.data());
          },
          "N cluster labels (numpy array; -1 outlier), or None for an unclustered map.")
      .def(
          "pose", [](const TaskMap& t, std::size_t i) { return fromPose(t.pose(i)); }, py::arg("i"),
          pydoc::kPose)
      .def(
          "nearest",
          [](const TaskMap& t, const Vec7& x, std::optional<int> c) {
            const Neighbor n = t.nearest(toPose(x), c);
            return py::make_tuple(n.index, n.distance);
          },
          py::arg("pose"), py::arg("cluster") = py::none(), pydoc::kNearest);
  bindTaskMapArrays(cls);
  bindTaskMapQueries(cls);
  bindClusterRanking(cls);
}

/// TaskMap.rank_clusters: the paper's initial cluster with the caller's IK and comfort.
void bindClusterRanking(py::class_<TaskMap>& cls) {
  cls.def(
      "rank_clusters",
      [](const TaskMap& t, const Vec7& object, py::function ik, py::function comfort,
         int member_tries) {
        IkFunction f = [&](const Pose& target) {
          py::object r = ik(fromPose(target));
          IkSolution s;
          if (r.is_none()) {
            s.message = "inverse kinematics returned None";
          } else {
            s.success = true;
            s.q = r.cast<Eigen::VectorXd>();
          }
          return s;
        };
        ComfortFunction g = [&](const Eigen::VectorXd& q) { return comfort(q).cast<double>(); };
        py::list out;
        RankOptions options;
        options.member_tries = member_tries;
        for (const ClusterRank& r : rankClusters(t, toPose(object), f, g, options)) {
          py::dict d;
          d["cluster"] = r.cluster;
          d["representative"] = r.representative;
          d["target"] = r.target;
          d["tried"] = r.tried;
          d["target_object"] = fromPose(r.target_object);
          d["target_world"] = fromPose(r.target_world);
          d["reachable"] = r.reachable;
          d["q"] = r.q;
          d["comfort"] = r.comfort;
          d["message"] = r.message;
          out.append(d);
        }
        return out;
      },
      py::arg("object_world"), py::arg("ik"), py::arg("comfort"), py::arg("member_tries") = 0,
      pydoc::kRankClusters);
}

/// TaskMap's queries: neighbours, proximity, quality, evaluate.
void bindTaskMapQueries(py::class_<TaskMap>& cls) {
  cls.def(
         "knn",
         [](const TaskMap& t, const Vec7& x, int k, std::optional<int> c) {
           return neighbours(t.knn(toPose(x), k, c));
         },
         py::arg("pose"), py::arg("k"), py::arg("cluster") = py::none(), pydoc::kKnn)
      .def(
          "radius",
          [](const TaskMap& t, const Vec7& x, double r, std::optional<int> c) {
            return neighbours(t.radius(toPose(x), r, c));
          },
          py::arg("pose"), py::arg("r"), py::arg("cluster") = py::none(), pydoc::kRadius)
      .def(
          "proximity",
          [](const TaskMap& t, const Vec7& x, std::optional<int> c) {
            return proximityDict(t.proximity(toPose(x), c));
          },
          py::arg("pose"), py::arg("cluster") = py::none(), pydoc::kProximity)
      .def(
          "quality",
          [](const TaskMap& t, const Vec7& x, std::optional<int> c,
             std::optional<std::string> mode) {
            return qualityDict(t.quality(toPose(x), c, modeOf(mode)));
          },
          py::arg("pose"), py::arg("cluster") = py::none(), py::arg("mode") = py::none(),
          pydoc::kQuality)
      .def(
          "evaluate",
          [](const TaskMap& t, const Vec7& x, std::optional<int> c) {
            return evaluationDict(t.evaluate(toPose(x), c));
          },
          py::arg("pose"), py::arg("cluster") = py::none(), pydoc::kEvaluate)
      .def(
          "session",
          [](const TaskMap& t, std::optional<double> margin, std::optional<int> c) {
            return EvaluationSession(t, c, margin);
          },
          py::arg("margin") = py::none(), py::arg("cluster") = py::none(), py::keep_alive<0, 1>(),
          pydoc::kSession)
      .def(
          "evaluate_batch",
          [](const TaskMap& t, const PoseRows& xs, std::optional<int> c) {
            BatchEvaluation b;
            {
              py::gil_scoped_release release;
              b = t.evaluateBatch(xs, c);
            }
            py::dict d;
            d["proximity"] = b.proximity;
            d["proximity_gradient"] = b.proximity_gradient;
            d["quality"] = b.quality;
            d["quality_gradient"] = b.quality_gradient;
            d["quality_bound"] = b.quality_bound;
            d["nearest"] = b.nearest;
            d["nearest_distance"] = b.nearest_distance;
            return d;
          },
          py::arg("poses"), py::arg("cluster") = py::none(), pydoc::kEvaluateBatch)
      .def(
          "nearest_batch",
          [](const TaskMap& t, const PoseRows& xs, std::optional<int> c) {
            Eigen::VectorXd dist;
            Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1> idx;
            {
              py::gil_scoped_release release;
              idx = t.nearestBatch(xs, &dist, c);
            }
            return py::make_tuple(idx, dist);
          },
          py::arg("poses"), py::arg("cluster") = py::none(), pydoc::kNearestBatch);
}

/// taskmap.Session: cached evaluation for an optimizer run.
void bindSession(py::module_& m) {
  py::class_<EvaluationSession>(m, "Session", pydoc::kSessionClass)
      .def(
          "evaluate",
          [](EvaluationSession& s, const Vec7& x) { return evaluationDict(s.evaluate(toPose(x))); },
          py::arg("pose"), pydoc::kSessionEvaluate)
      .def_property_readonly(
          "stats",
          [](const EvaluationSession& s) {
            py::dict d;
            d["calls"] = s.stats().calls;
            d["anchors"] = s.stats().anchors;
            d["fallbacks"] = s.stats().fallbacks;
            return d;
          },
          "dict: calls (evaluations), anchors (index searches that refilled the cache), "
          "fallbacks (evaluations the cache could not answer exactly).")
      .def_property_readonly("margin", &EvaluationSession::margin,
                             "How far (pose metric, metres) iterates may move from the cache's "
                             "anchor.")
      .def_property_readonly("cluster", &EvaluationSession::cluster,
                             "The cluster evaluated against, or None for the whole map.")
      .def("reset", &EvaluationSession::reset, pydoc::kSessionReset);
}

/// load, seal and the frame, gradient and cost helpers.
void bindFunctions(py::module_& m) {
  m.def(
      "load",
      [](const std::string& path, const py::kwargs& kw) {
        return TaskMap::load(path, makeOptions(kw));
      },
      py::arg("path"), pydoc::kLoad);
  m.def(
      "seal",
      [](const std::string& path) {
        py::gil_scoped_release release;
        sealMap(path);
      },
      py::arg("path"), pydoc::kSeal);
  m.def("data_dir", &dataDir, pydoc::kDataDir);
  m.def(
      "hand_in_object",
      [](const Vec7& h, const Vec7& o) { return fromPose(handInObject(toPose(h), toPose(o))); },
      py::arg("hand_world"), py::arg("object_world"), pydoc::kHandInObject);
  m.def(
      "hand_gradient_to_world",
      [](const Twist& g, const Vec7& o) {
        return Eigen::VectorXd(handGradientToWorld(g, toPose(o)));
      },
      py::arg("gradient"), py::arg("object_world"), pydoc::kHandGradientToWorld);
  m.def(
      "object_gradient_to_world",
      [](const Twist& g, const Vec7& h, const Vec7& o) {
        return Eigen::VectorXd(objectGradientToWorld(g, toPose(h), toPose(o)));
      },
      py::arg("gradient"), py::arg("hand_world"), py::arg("object_world"),
      pydoc::kObjectGradientToWorld);
  m.def(
      "joint_gradient",
      [](const Twist& g, const Vec7& h, const Vec7& o, const Eigen::MatrixXd& jh,
         std::optional<Eigen::MatrixXd> jo) {
        return jointGradient(g, toPose(h), toPose(o), jh, jo.value_or(Eigen::MatrixXd()));
      },
      py::arg("gradient"), py::arg("hand_world"), py::arg("object_world"), py::arg("hand_jacobian"),
      py::arg("object_jacobian") = py::none(), pydoc::kJointGradient);
  m.def(
      "pose_distance",
      [](const Vec7& a, const Vec7& b, double rho) {
        return poseDistance(toPose(a), toPose(b), rho);
      },
      py::arg("a"), py::arg("b"), py::arg("rho") = kDefaultRotationScale, pydoc::kPoseDistance);
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "Grasp task maps: load a map, query nearest grasps, proximity and quality criteria.";
  static py::exception<Error> error(m, "Error", PyExc_ValueError);
  error.attr("__doc__") = pydoc::kError;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });

  bindTrajectory(m);

  bindTaskMap(m);
  bindSession(m);
  bindFunctions(m);
}
