#pragma once
/// @file acronym.hpp
/// Export to and import from the per-object HDF5 layout of ACRONYM (Eppner, Mousavian, Fox,
/// "ACRONYM: A Large-Scale Grasp Dataset Based on Simulation", NVlabs/acronym), so that tools
/// written for that dataset read our maps and its grasps become task maps.
///
/// Layout (datasets; h5py reads them as `f["object/scale"][()]`, as acronym_tools does):
///   grasps/transforms                         f64 N x 4 x 4, gripper base frame -> object
///                                             frame (mesh coordinates times object/scale), m
///   grasps/qualities/flex/object_in_gripper   i64 (N), 1 = success; we write force closure
///   grasps/qualities/taskmap/epsilon          f64 (N), Ferrari-Canny epsilon (our addition;
///                                             ACRONYM readers ignore it)
///   object/file      string   mesh file the grasps refer to
///   object/scale     f64      scale applied to the mesh file
///   object/mass      f64      kg (volume * density)
///   object/density   f64      kg/m^3
///   object/friction  f64      Coulomb friction coefficient
///   object/com       f64 (3)  centre of mass, metres, object frame
///   object/volume    f64      m^3
///   object/inertia   f64 3x3  inertia about the centre of mass, kg m^2 (uniform density)
///   gripper/type           string  gripper (our hand) name
///   gripper/configuration  f64 (J) joint values of the hand's open configuration when known;
///                                  empty for our maps (they store closed values per grasp)

///
/// Frames: ACRONYM's transforms place the gripper's *base* frame (for its Franka gripper the
/// hand link, `panda_hand`, at the flange); task maps store the *palm* frame. With B the palm
/// frame in the base frame (base_to_palm), a palm pose P and an ACRONYM transform T relate by
///   P = T * B  (import),   T = P * B^-1  (export).
/// The default B is ACRONYM's Franka gripper: a translation of 0.1034 m along the base z axis
/// (the approach axis), from the hand link to the point between the fingertips
/// (kAcronymFrankaPalmOffset); for a hand URDF whose root is the base frame, B is the hand's
/// root-to-palm transform (`taskmap import/export --hand`). See docs/ACRONYM.md.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/clustering/clustering.hpp"
#include "taskmap/mapstore/task_map_data.hpp"

namespace taskmap {

/// Offset of the palm frame from ACRONYM's Franka gripper base along its z (approach) axis, m.
inline constexpr double kAcronymFrankaPalmOffset = 0.1034;

/// Palm frame in ACRONYM's gripper base frame for its Franka gripper: z by 0.1034 m.
Eigen::Isometry3d acronymFrankaBaseToPalm();

/// Options of writeAcronym.
struct AcronymExportOptions {
  std::string object_file;  ///< object/file; "" writes "<object name>.obj"
  double density = 1000.0;  ///< kg/m^3 for object/density and object/mass; > 0
  /// Palm frame in the gripper base frame: transforms written are pose * base_to_palm^-1.
  Eigen::Isometry3d base_to_palm = acronymFrankaBaseToPalm();
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
};

/// The content of an ACRONYM grasp file.
struct AcronymGrasps {
  std::string path;                            ///< the file read ("" when built in memory)
  std::vector<Eigen::Matrix4d> transforms;     ///< N homogeneous transforms, metres
  std::vector<std::uint8_t> success;           ///< N, object_in_gripper as 0 / 1
  std::optional<std::vector<double>> epsilon;  ///< N, only in files written by taskmap
  std::string object_file;
  double object_scale = 1.0;
  std::optional<double> object_mass;
  std::optional<double> object_density;
  std::optional<double> object_friction;
  std::optional<double> object_volume;
  std::optional<Eigen::Vector3d> object_com;
  std::string gripper_type;
  std::vector<double> gripper_configuration;
};

/// Writes the map's grasps in ACRONYM's layout, atomically (temporary file beside path, then
/// rename). Inertia is computed from the map's mesh at the given density. No HDF5 object
/// times: the same map and options give the same bytes.
/// Throws Error naming the file when it cannot be written.
void writeAcronym(const std::string& path, const TaskMapData& map,
                  const AcronymExportOptions& options = {});

/// Reads an ACRONYM grasp file (the dataset's own or one written by writeAcronym). Accepts
/// any numeric type for numbers, fixed or variable-length strings. Throws Error naming the
/// file and the missing or malformed dataset. Foreign files carry no seal, so what is read is
/// bounded: at most 1 GiB, read whole into memory and parsed by HDF5 from there; a dataset
/// may declare at most ~1032 times the file's size in values (deflate's best ratio), a
/// fixed-length string at most 1 MiB. HDF5 itself may still stop on a crafted file.
AcronymGrasps readAcronym(const std::string& path);

/// Options of acronymToMap.
struct AcronymImportOptions {
  bool successful_only = false;  ///< keep only grasps with object_in_gripper = 1
  bool cluster = true;           ///< run clusterGrasps on the imported poses (needs >= 2)
  /// Palm frame in the gripper base frame: imported poses are transform * base_to_palm.
  Eigen::Isometry3d base_to_palm = acronymFrankaBaseToPalm();
  ClusteringOptions clustering;  ///< options of that clustering
  /// Throws Error naming the option when a value is out of range.
  void validate() const;
};

/// Turns ACRONYM grasps into a task map for object (mesh already scaled by
/// grasps.object_scale, in metres). Poses are the palm frames transform * base_to_palm
/// (rotation re-orthonormalised;
/// a transform whose rotation is not a rotation within 1e-6 is refused). force_closure is
/// object_in_gripper; epsilon is the file's taskmap epsilon when present, else
/// object_in_gripper as 0 / 1 (ACRONYM has no epsilon). Contacts are absent
/// (contacts_available = false), joints empty, volumes 0. Throws Error on an empty result.
TaskMapData acronymToMap(const AcronymGrasps& grasps, const MapObject& object,
                         const AcronymImportOptions& options = {});

/// Inertia about the centre of mass of a closed mesh (vertices V x 3 in metres, outward
/// faces) at uniform density (kg/m^3), kg m^2.
Eigen::Matrix3d meshInertia(
    const RowMatrixXd& vertices,
    const Eigen::Matrix<std::int64_t, Eigen::Dynamic, 3, Eigen::RowMajor>& faces,
    const Eigen::Vector3d& center_of_mass, double density);

}  // namespace taskmap
