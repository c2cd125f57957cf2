#pragma once
/// @file data_dir.hpp
/// Where taskmap (the tool, the library, the Python package) finds its bundled data: the reference
/// hands (hands/<name>/), objects (objects/), reference maps (maps/), robots
/// (robots/<name>/<name>.urdf) and the regression suite (regression/cases.json,
/// regression/golden/). Every install carries it in <prefix>/share/taskmap: `cmake --install`
/// (cmake/TaskMapData.cmake) and `pip install .` (the wheel puts it in <venv>/share/taskmap,
/// beside <venv>/lib/libtaskmap_core).

#include <string>
#include <vector>

namespace taskmap {

/// The data directory, the first of, in this order:
///  1. $TASKMAP_DATA_DIR if set (an error if it is not a directory);
///  2. `<directory of the executable>/../share/taskmap` (the taskmap tools: the install tree's
///     share/taskmap; the build tree stages the same layout in <build>/share/taskmap);
///  3. `<directory of libtaskmap_core>/../share/taskmap` (a program other than the tools: the
///     Python package, whose wheel installs <venv>/share/taskmap beside <venv>/lib, or a user's
///     executable linked to an installed taskmap).
/// Throws Error saying how to set TASKMAP_DATA_DIR when none exists.
std::string dataDir();

/// The model file of a bundled hand: `<dataDir()>/hands/<name>/<name>.urdf`, else
/// `<name>/<name>.xml` (an MJCF hand). Throws Error listing the bundled hands when there is none
/// of that name, with "did you mean" the closest bundled name (or, for a path, the closest URDF
/// or MJCF file in its folder).
std::string bundledHandUrdf(const std::string& name);

/// A hand argument as a URDF path: the path itself if it exists, else the bundled hand of that
/// name (bundledHandUrdf, which throws Error listing the bundled hands).
std::string resolveHandUrdf(const std::string& hand);

/// A map argument as a file: the path itself when it exists, else the bundled map of that name
/// (`<dataDir()>/maps/<name>.h5`, e.g. "basket_humanoid"). Throws Error naming both.
std::string resolveMapFile(const std::string& map);

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
/// the closest bundled objects (<dataDir()>/objects) by name (a bare name gets bundled names:
/// "baskt" -> 'basket').
void requireObjectFile(const std::string& path);

/// The names of the bundled objects: the stems of `<dataDir()>/objects/*.obj` ("basket",
/// "mug", ...), sorted; empty when there is no data directory.
std::vector<std::string> bundledObjectNames();

/// An object argument as it names a file: the path itself when it exists or is not a bundled
/// object's name, else `<dataDir()>/objects/<name>.obj`. Never throws (a missing file is the
/// caller's to report).
std::string objectFileOrBundled(const std::string& object);

/// An object argument as a mesh path, named like a hand: the path itself when it exists, else
/// the bundled object of that name (`<dataDir()>/objects/<name>.obj` for "basket"; a name has
/// no '/' and no extension). Otherwise throws requireObjectFile's Error ("no such file; did you
/// mean ...").
std::string resolveObjectFile(const std::string& object);

}  // namespace taskmap
