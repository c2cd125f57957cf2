#pragma once
/// @file mesh_options.hpp
/// The mesh repair options shared by `mesh-info` and `build`: --no-repair, --repair wrap,
/// --wrap-alpha, --wrap-offset (MeshLoadOptions in meshes/include/taskmap/meshes/object_model.hpp).

#include <string>

#include <CLI/CLI.hpp>

#include "taskmap/meshes/object_model.hpp"

namespace taskmap::cli {

/// Parsed repair options.
struct MeshRepairArgs {
  bool no_repair = false;    ///< refuse meshes that need repair
  std::string repair;        ///< "" (default repairs) or "wrap" (also close open surfaces)
  double wrap_alpha = 0.0;   ///< metres, 0: automatic
  double wrap_offset = 0.0;  ///< metres, 0: automatic
};

/// Adds the repair options to `cmd`.
void addMeshRepairOptions(CLI::App* cmd, MeshRepairArgs& args);

/// Adds --package-path DIR (repeatable) to a command that takes a hand: each DIR is put before
/// the entries of ROS_PACKAGE_PATH, where package:// mesh paths of URDFs are looked up
/// (taskmap/hands/ros_package.hpp), in the order given.
void addPackagePathOption(CLI::App* cmd);

/// Sets repair and wrap fields of `options`; throws Error on contradicting options.
void applyMeshRepairArgs(const MeshRepairArgs& args, MeshLoadOptions& options);

}  // namespace taskmap::cli
