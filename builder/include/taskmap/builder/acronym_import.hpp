#pragma once
/// @file acronym_import.hpp
/// An ACRONYM grasp file as a task map file (what `taskmap import` and `taskmap.import_acronym`
/// compute): read the foreign file, load the object mesh at the file's scale, turn the grasps
/// into palm poses (mapstore/acronym.hpp), cluster them and write the map. The foreign file
/// carries no seal, so the whole import runs in a child process with memory and CPU limits
/// (taskmap/core/bounded_child.hpp): a file that crashes or hangs HDF5 is refused and nothing is
/// written.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "taskmap/mapstore/acronym.hpp"

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
  int cpu_seconds = 600;        ///< CPU-time limit of the child process, seconds
  double memory_gib = 16.0;     ///< memory limit of the child process beyond the caller's, GiB
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
};

/// Imports options.acronym with the object mesh options.object into options.output (the guard
/// against overwriting inputs is the caller's: core/output_guard.hpp). Throws Error naming the
/// file and the problem (a missing mesh names the one the file refers to; a crash or a limit of
/// the child names the limit); nothing is written then.
AcronymFileImport importAcronymFile(const AcronymFileImportOptions& options);

}  // namespace taskmap
