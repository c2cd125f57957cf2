#pragma once
/// @file acronym_frame.hpp
/// The --palm-offset / --hand options of `import` and `export`: which transform takes ACRONYM's
/// gripper base frame to the palm frame of task maps (acronymBaseToPalm in
/// builder/include/taskmap/builder/acronym_import.hpp).

#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <Eigen/Geometry>

namespace taskmap::cli {

/// Parsed frame options.
struct AcronymFrameArgs {
  std::optional<double> palm_offset;  ///< metres along the base z axis
  std::string hand;                   ///< hand URDF or bundled hand name: its root-to-palm
};

/// Adds --palm-offset and --hand to `cmd`.
void addAcronymFrameOptions(CLI::App* cmd, AcronymFrameArgs& args);

/// One line saying which transform was used.
std::string describeBaseToPalm(const AcronymFrameArgs& args, const Eigen::Isometry3d& t);

}  // namespace taskmap::cli
