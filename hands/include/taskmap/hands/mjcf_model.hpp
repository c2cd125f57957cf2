#pragma once
/// @file mjcf_model.hpp
/// An MJCF (MuJoCo XML) hand as the same plain-data tree the URDF reader gives (urdf_model.hpp),
/// with the dynamics the model states (hand_dynamics.hpp): what HandModel::load reads for a
/// `.xml` hand. Bodies become links (depth-first in document order; a body with k joints becomes
/// k links, the first k - 1 named "<body>/<joint>" and without geometry), hinge and slide joints
/// become revolute and prismatic joints (a body without joints hangs by a fixed joint named
/// "<body>_fixed"), colliding geoms become collision shapes (visual geoms, contype = conaffinity
/// = 0, are skipped), <equality><joint> couplings and fixed tendons driven by one actuator become
/// mimic joints. Everything else taskmap cannot represent is refused naming the element, its line
/// and file. Supported elements and rules: meshes/hands/README.md, "MJCF support"; limits on
/// hostile files: docs/HOSTILE_INPUTS.md. TinyXML parses (kept private to hands). Units: metres,
/// radians (a model's degrees are converted).

#include <cstddef>
#include <string>
#include <vector>

#include "taskmap/hands/hand_dynamics.hpp"
#include "taskmap/hands/urdf_model.hpp"

namespace taskmap {

/// An MJCF hand as plain data.
struct MjcfModel {
  /// The kinematic tree: links depth-first from the hand's top body (document order), joints,
  /// collision shapes (mesh paths relative to the model's folder), inertials, mimic couplings.
  UrdfModel tree;
  /// What the model states about its dynamics, indexed like tree (links, joints, collisions).
  HandDynamics dynamics;
  /// What was skipped and why (missing visual meshes, ignored free joint, unused actuators).
  std::vector<std::string> warnings;
  /// Every file read: the model first, then its <include>s in the order they were read.
  std::vector<std::string> files;
};

/// Reads the MJCF text `xml` of the file `path` (its <include>s are read from disk, relative to
/// the model's folder and never outside it). Throws Error "MJCF '<path>': <element> at line N
/// [of '<included file>']: <what is wrong and what to do>" for anything taskmap cannot use, and
/// for files beyond the limits (nesting, element count, included files, file size).
MjcfModel readMjcfModel(const std::string& xml, const std::string& path);

/// True when the first element of `xml` is <mujoco> (an MJCF model; a URDF's is <robot>).
bool isMjcfText(const std::string& xml);

/// Deepest element nesting an MJCF hand may have, counted across its <include>s.
constexpr int kMaxMjcfDepth = 64;
/// Most elements an MJCF hand may have across its files (a Menagerie hand has a few hundred).
constexpr std::size_t kMaxMjcfElements = 20000;
/// Most files an MJCF hand may be assembled from (the model and its <include>s).
constexpr std::size_t kMaxMjcfFiles = 64;
/// Largest MJCF file taskmap reads, bytes.
constexpr std::size_t kMaxMjcfFileBytes = std::size_t{8} << 20;

}  // namespace taskmap
