#pragma once
/// @file acronym_import.hpp
/// An ACRONYM grasp file as a task map file (what `taskmap import` and `taskmap.import_acronym`
/// compute): read the foreign file, load the object mesh at the file's scale, turn the grasps
/// into palm poses (mapstore/acronym.hpp); with a hand, close its jaws at each pose for the
/// grasps' joint values (grasp_sim/jaw_closing.hpp) and record the hand, so that the map can be
/// validated (docs/ACRONYM.md); cluster them and write the map. The foreign file
/// carries no seal, so the whole import runs in a child process with memory and CPU limits
/// (taskmap/core/bounded_child.hpp): a file that crashes or hangs HDF5 is refused and nothing is
/// written.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "taskmap/clustering/clustering.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/mapstore/acronym.hpp"
#include "taskmap/mapstore/task_map_data.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {

/// The palm frame in ACRONYM's gripper base frame: the root-to-palm transform of `hand` (a hand
/// URDF or bundled hand name, for a URDF whose root is the base frame), a translation along z
/// by `palm_offset` metres, else ACRONYM's Franka gripper (z by 0.1034 m). Throws Error naming
/// --palm-offset and --hand when both are given, or the offset is not finite.
Eigen::Isometry3d acronymBaseToPalm(const std::optional<double>& palm_offset,
                                    const std::string& hand);

/// Options of importAcronymFile (the options of `taskmap import`).
struct AcronymFileImportOptions {
  std::string acronym;          ///< ACRONYM grasp file (.h5)
  std::string object;           ///< the object's mesh file (any format assimp reads)
  std::string output;           ///< task map to write (.h5), atomically
  double scale = 0.0;           ///< mesh file units to metres; 0: the file's object/scale
  bool timestamp = false;       ///< store the current time as created_utc
  AcronymImportOptions import;  ///< successful_only, clustering, base_to_palm
  /// The gripper (URDF path or bundled hand name, `--hand`; its root link ACRONYM's gripper base
  /// frame): its jaws are closed at every pose for the joint values and the map records it
  /// (closeImportedJaws). Empty: poses only (the map cannot be validated). The caller sets
  /// import.base_to_palm from it too (acronymBaseToPalm).
  std::string hand;
  int cpu_seconds = 600;     ///< CPU-time limit of the child process, seconds
  double memory_gib = 16.0;  ///< memory limit of the child process beyond the caller's, GiB
  /// Throws Error naming the option (as `taskmap import` spells it) when a value is out of range.
  void validate() const;
};

/// What importAcronymFile wrote.
struct AcronymFileImport {
  std::size_t grasps = 0;               ///< grasps in the map
  std::size_t successes = 0;            ///< of them with force closure (object_in_gripper = 1)
  std::optional<std::size_t> clusters;  ///< clusters of the map; none when not clustered
  std::string object_name;              ///< the object's name (its file's stem)
  double scale = 1.0;                   ///< the scale the mesh was loaded at
  bool jaws_closed = false;             ///< a hand was given: the grasps carry joint values
  std::size_t jaws_missed = 0;          ///< grasps dropped because the jaws miss the object
  std::size_t jaws_overlap = 0;         ///< grasps kept whose open jaws intersect the object
};

/// What closeImportedJaws found, grasps by their index in the source file.
struct ImportedJaws {
  std::size_t closed = 0;           ///< grasps kept (overlaps included)
  std::vector<std::size_t> missed;  ///< dropped: a jaw passes the object, or both close on nothing
  std::vector<std::size_t> overlaps;  ///< kept: a jaw intersects the object with the jaws open
};

/// Gives the grasps of an imported map (palm poses without joint values, acronymToMap) the
/// joint values of `hand`'s jaws closed from open at each pose (JawCloser: the object, free to
/// slide between the jaws, is pushed by the first jaw that touches until the other touches too),
/// keeping every pose as it is; drops the grasps whose jaws miss the object (the sampling
/// outcome `jaws_missed` counts them) and keeps those whose open jaws intersect it (another
/// gripper model's grasps: the hold test's penetration check decides; ImportedJaws, by
/// `source[i]`, grasp i's index in the source file), re-clusters the rest with `clustering`
/// when given (its rotation_scale the map's) and at least two remain, and records the hand:
/// name, URDF SHA-256, joint and link names, and in the sampling parameters "hand" (`hand_path`,
/// where validation finds it), "hold_closing": "from_open" (the hold test closes the jaws from
/// open, validate_map.hpp mapClosesFromOpen), "jaws_missed" and "jaws_overlap" (source
/// indices). Throws Error naming the hand when it is not a parallel-jaw gripper, when `source`
/// does not hold one index per grasp, or when the jaws miss the object at every pose.
ImportedJaws closeImportedJaws(TaskMapData* map, const HandModel& hand,
                               const std::string& hand_path, const ObjectModel& object,
                               const std::vector<std::size_t>& source,
                               const std::optional<ClusteringOptions>& clustering);

/// Imports options.acronym with the object mesh options.object into options.output (the guard
/// against overwriting inputs is the caller's: core/output_guard.hpp). Throws Error naming the
/// file and the problem (a missing mesh names the one the file refers to; a crash or a limit of
/// the child names the limit); nothing is written then.
AcronymFileImport importAcronymFile(const AcronymFileImportOptions& options);

}  // namespace taskmap
