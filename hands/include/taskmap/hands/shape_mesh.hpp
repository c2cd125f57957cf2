#pragma once
/// @file shape_mesh.hpp
/// Hand collision shapes as triangle meshes, alone or posed by a grasp, for pictures and scene
/// files (`taskmap inspect --png`, `taskmap export --format glb|ply`).

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/core/triangle_mesh.hpp"
#include "taskmap/hands/hand_model.hpp"

namespace taskmap {

/// Closed triangle mesh of one collision shape in its own frame (metres, faces oriented
/// outwards): a box exactly (8 vertices, 12 triangles), a cylinder as a 24-sided prism, a
/// sphere as a UV sphere (8 latitudes x 16 longitudes, vertices on the sphere), a convex shape
/// as the convex hull of its points (coplanar facets fanned). Empty for a degenerate shape
/// (zero size, or convex points on a plane).
TriangleMesh collisionShapeMesh(const CollisionShape& shape);

/// One triangle mesh per link of `hand` (links() order): the link's collision shapes at joint
/// values q (jointNames() order, clamped to the limits) in the frame that `palm_pose` maps the
/// palm frame into (a grasp's pose: palm frame -> object frame). A link without collision
/// shapes gets an empty mesh. Throws Error when q has the wrong size.
std::vector<TriangleMesh> posedLinkMeshes(const HandModel& hand, const Eigen::Isometry3d& palm_pose,
                                          const Eigen::VectorXd& q);

}  // namespace taskmap
