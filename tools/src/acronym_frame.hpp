#pragma once
/// @file acronym_frame.hpp
/// The --palm-offset / --hand options of `import` and `export`: which transform takes ACRONYM's
/// gripper base frame to the palm frame of task maps
/// (mapstore/include/taskmap/mapstore/acronym.hpp).

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

/// The palm frame in the gripper base frame: the hand's root-to-palm transform with --hand, a
/// translation along z by --palm-offset, else ACRONYM's Franka gripper (z by 0.1034 m).
/// Throws Error when both options are given.
Eigen::Isometry3d baseToPalm(const AcronymFrameArgs& args);

/// One line saying which transform was used.
std::string describeBaseToPalm(const AcronymFrameArgs& args, const Eigen::Isometry3d& t);

}  // namespace taskmap::cli
