#pragma once
/// @file data_dir.hpp
/// Where taskmap (the tool, the library, the Python package) finds its bundled data: the reference
/// hands (hands/<name>/), objects (objects/), robots (robots/<name>/<name>.urdf) and the regression
/// suite (regression/cases.json, regression/golden/).

#include <string>
#include <vector>

namespace taskmap {

/// The data directory: $TASKMAP_DATA_DIR if set, else `<directory of the
/// executable>/../share/taskmap` (the install tree's share/taskmap; the build tree stages the same
/// layout in <build>/share), else `<directory of libtaskmap_core>/../share/taskmap` (a program
/// other than the tool: Python, a user's executable). Throws Error saying how to set
/// TASKMAP_DATA_DIR when neither exists.
std::string dataDir();

/// The URDF of a bundled hand: `<dataDir()>/hands/<name>/<name>.urdf`. Throws Error listing the
/// bundled hands when there is none of that name, with "did you mean" the closest bundled name
/// (or, for a path, the closest URDF in its folder).
std::string bundledHandUrdf(const std::string& name);

/// A hand argument as a URDF path: the path itself if it exists, else the bundled hand of that
/// name (bundledHandUrdf, which throws Error listing the bundled hands).
std::string resolveHandUrdf(const std::string& hand);

/// The sidecar a hand URDF is read with: <dir>/<stem>.hand.json.
std::string handSidecarPath(const std::string& urdf);

/// The candidates closest to `name` (case-insensitive edit distance at most a third of its
/// length, at least 1; or one contains the other), closest first; empty when none is close.
std::vector<std::string> closestNames(const std::string& name,
                                      const std::vector<std::string>& candidates);

/// "; did you mean 'a'?" (or "'a' or 'b'?") for closestNames, "" when none is close.
std::string didYouMean(const std::string& name, const std::vector<std::string>& candidates);

/// Throws Error("cannot open mesh file '<path>': no such file[; did you mean ...?]") when the
/// object mesh `path` does not exist: the suggestions are the closest files of its folder and
/// the closest bundled objects (<dataDir()>/objects) by name.
void requireObjectFile(const std::string& path);

}  // namespace taskmap
