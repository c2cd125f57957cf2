#pragma once
/// @file glb_export.hpp
/// glTF 2.0 binary (GLB) of a reaching trajectory for Blender and other viewers: one node per
/// body with its collision primitives triangulated, the object mesh at its pose, and one
/// animation with a translation and a rotation channel per moving body (docs/REACHING.md,
/// "Trajectory files and GLB export").

#include <string>

#include "taskmap/mapstore/trajectory_file.hpp"

namespace taskmap {

/// The GLB file's bytes. Node "world" (rotation -90 deg about x: the robot's z-up world in
/// glTF's y-up convention) holds one node per body (named as the body, world pose at step 0,
/// a mesh when the body has primitives) and "object_mesh" (when the record has a mesh).
/// Materials "robot" (orange), "hand" (blue), "environment" (grey), "object" (brown).
/// Animation "reach": key t = k dt for every row k, LINEAR interpolation. Metres, seconds.
std::string glbBytes(const TrajectoryRecord& record);

/// Writes glbBytes(record) atomically to path; throws Error naming the path.
void writeGlb(const TrajectoryRecord& record, const std::string& path);

}  // namespace taskmap
