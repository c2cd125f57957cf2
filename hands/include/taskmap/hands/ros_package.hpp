#pragma once
/// @file ros_package.hpp
/// ROS conventions a URDF from a robot description package brings: `package://PKG/path` mesh
/// URIs, and `.xacro` files that must be expanded to URDF first.

#include <string>
#include <vector>

namespace taskmap {

/// The folders searched for ROS packages besides the package that holds the URDF: the entries
/// of the ROS_PACKAGE_PATH environment variable (colon-separated; `taskmap --package-path DIR`
/// prepends DIR), in order.
std::vector<std::string> rosPackagePath();

/// Resolves `package://PKG/relative/path` for a URDF at `urdf_path` to a file path: PKG is the
/// first of (1) a folder on rosPackagePath() that is PKG (its name, or its package.xml's
/// <name>), holds PKG directly, or holds it up to three levels down; (2) the package that
/// contains the URDF: walking up from the URDF's folder, a folder whose package.xml names PKG or
/// whose name is PKG, or a folder holding a sibling PKG. Throws Error saying where it looked and
/// what to pass (`--package-path DIR`, ROS_PACKAGE_PATH) when PKG is not found. `what` prefixes
/// the message. Any other string is returned unchanged.
std::string resolvePackageUri(const std::string& uri, const std::string& urdf_path,
                              const std::string& what);

/// Throws Error when `path` is a xacro file (its name ends in .xacro, or `text` has xacro
/// elements), saying how to expand it to a URDF; `what` names the file's role ("hand URDF");
/// `hand`: also name the sidecar and the self-collision check of `taskmap hand-info`.
void refuseXacro(const std::string& path, const std::string& text, const std::string& what,
                 bool hand);

}  // namespace taskmap
