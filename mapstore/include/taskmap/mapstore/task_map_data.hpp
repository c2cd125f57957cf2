#pragma once
/// @file task_map_data.hpp
/// Everything a task map file holds (schema version 2, mapstore/SCHEMA.md), in memory.
/// Plain data: mapstore reads and writes it, integration queries it, tools show it.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "taskmap/clustering/clustering.hpp"
#include "taskmap/core/pose.hpp"

namespace taskmap {

/// Schema version this library writes; the reader refuses newer ones.
constexpr int kMapSchemaVersion = 2;

/// Row-major matrix of doubles (HDF5 layout).
using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// The object a map was built for (/object).
struct MapObject {
  std::string name;
  std::string source_sha256;  ///< SHA-256 of the source mesh file ("" if none)
  double scale = 1.0;         ///< scale applied to the source file
  double volume = 0.0;        ///< m^3
  Eigen::Vector3d center_of_mass = Eigen::Vector3d::Zero();               ///< metres, object frame
  double torque_scale = 0.0;                                              ///< metres
  RowMatrixXd vertices;                                                   ///< V x 3, metres
  Eigen::Matrix<std::int64_t, Eigen::Dynamic, 3, Eigen::RowMajor> faces;  ///< F x 3
};

/// The hand a map was built with (/hand).
struct MapHand {
  std::string name;
  std::string urdf_sha256;
  std::vector<std::string> joint_names;  ///< J actuated joints, order of MapGrasps::joints
  /// L hand links in HandModel::links() order (/hand/link_names): MapGrasps::contact_links
  /// indexes it. Empty for maps written before it was stored and for imported maps.
  std::vector<std::string> link_names;
};

/// How trials were sampled (/sampling).
struct MapSampling {
  std::string sampler;  ///< "volume" or "surface"
  std::uint64_t seed = 0;
  std::uint64_t trials = 0;                       ///< trials simulated
  std::map<std::string, std::uint64_t> outcomes;  ///< trials per outcome status name
  std::string params_json = "{}";                 ///< every build parameter, JSON object
};

/// How grasps were scored (/quality).
struct MapQuality {
  double friction = 0.5;
  int cone_edges = 8;
  std::string contact_model = "point_with_friction";
};

/// The grasps (/grasps), one row each; contacts of grasp i are rows
/// contact_offsets[i] .. contact_offsets[i+1]-1 of the contact arrays.
struct MapGrasps {
  RowMatrixXd pose;                           ///< N x 7: x y z qw qx qy qz, palm in object frame
  RowMatrixXd joints;                         ///< N x J, radians or metres
  std::vector<std::uint8_t> force_closure;    ///< N
  std::vector<double> epsilon;                ///< N
  std::vector<double> volume;                 ///< N
  std::vector<std::int64_t> contact_offsets;  ///< N + 1, monotone, from 0 to M
  RowMatrixXd contact_points;                 ///< M x 3, metres, object frame
  RowMatrixXd contact_normals;                ///< M x 3, outward unit normals
  std::vector<double> contact_depths;         ///< M, metres
  std::vector<std::int32_t> contact_links;    ///< M, hand link index
  bool contacts_available = true;             ///< false for imported maps without contacts
  double rotation_scale = kDefaultRotationScale;  ///< rho of the pose metric, metres/radian

  /// Number of grasps.
  std::size_t size() const { return static_cast<std::size_t>(pose.rows()); }
  /// Pose of grasp i.
  Pose poseAt(std::size_t i) const;
};

/// Physics hold labels of the grasps (/grasps/hold*, /validation; mapstore/SCHEMA.md), written
/// by taskmap::validate (docs/VALIDATION.md). Every vector has one entry per grasp.
struct MapValidation {
  static constexpr std::uint8_t kNotTested = 255;  ///< hold and status of a grasp not tested
  std::vector<std::uint8_t> hold;                  ///< 1 holds, 0 does not, kNotTested
  std::vector<std::uint8_t> status;     ///< HoldStatus code (0 holds .. 4 unstable), kNotTested
  std::vector<double> translation;      ///< largest object displacement, metres (-1 not tested)
  std::vector<double> rotation;         ///< largest object rotation, radians (-1 not tested)
  std::vector<std::int32_t> direction;  ///< failing push 0..5 (-x +x -y +y -z +z), -1 none
  std::string protocol;                 ///< protocol name, e.g. "dexgraspbench_fc"
  std::string engine;                   ///< physics engine and version, e.g. "MuJoCo 2.2.2"
  std::string params_json = "{}";       ///< every protocol parameter, JSON object
  /// The robust label's variants and thresholds (JSON object; "variants" names them in test
  /// order), or "" when the map has no robust labels: then the five robust vectors are empty.
  std::string robust_json;
  std::vector<std::uint8_t> robust;  ///< 1 robust, 0 not, kNotTested
  std::vector<double> robust_share;  ///< variants held / variants tested; -1 not tested
  /// Largest displacement of the object from its closed state under the pushes, over the
  /// variants tested, metres; -1 not tested.
  std::vector<double> push_translation;
  std::vector<double> push_rotation;  ///< the same for its rotation, radians; -1 not tested
  /// Grasps x variants, row-major: 1 the variant held, 0 it failed, kNotTested.
  std::vector<std::uint8_t> variant_held;
  /// Grasps tested (hold != kNotTested).
  std::size_t tested() const;
  /// Grasps that hold (hold == 1).
  std::size_t holding() const;
  /// Grasps that hold robustly (robust == 1; 0 without robust labels).
  std::size_t robustCount() const;
  /// Variants of the robust label (the length of robust_json's "variants"; 0 without).
  std::size_t variantCount() const;
};

/// A whole task map.
struct TaskMapData {
  std::string generator;    ///< "taskmap <version>"
  std::string created_utc;  ///< ISO 8601
  MapObject object;
  MapHand hand;
  MapSampling sampling;
  MapQuality quality;
  MapGrasps grasps;
  std::optional<ClusteringResult> clustering;  ///< /grasps/cluster, /clusters, /clustering
  std::optional<MapValidation> validation;     ///< /grasps/hold*, /validation

  /// Checks every invariant the reader checks (shapes, offsets, unit quaternions, finite
  /// values); throws Error naming the first violated dataset.
  void validate() const;
};

}  // namespace taskmap
