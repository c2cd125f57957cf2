#pragma once
/// @file primitive_distance.hpp
/// Exact distance and closest points between two posed sphere-swept primitives (capsule =
/// segment swept by a sphere, sphere-swept rectangle), paper section 1.2.1.2. Units: metres.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "taskmap/reaching/robot_model.hpp"

namespace taskmap {

/// Closest points between two primitives A and B, world frame.
struct PrimitiveDistance {
  /// Signed distance between the swept surfaces: core distance - r_A - r_B (negative when the
  /// primitives overlap), metres.
  double distance = 0.0;
  double core_distance = 0.0;  ///< distance between the cores (segment / rectangle), >= 0
  Eigen::Vector3d core_a = Eigen::Vector3d::Zero();   ///< closest point on A's core
  Eigen::Vector3d core_b = Eigen::Vector3d::Zero();   ///< closest point on B's core
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  ///< core_a + r_A normal (surface point)
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  ///< core_b - r_B normal (surface point)
  /// Unit direction from A to B: (core_b - core_a) / core_distance; when the cores touch
  /// (core_distance < 1e-12) the direction between the primitive centres, else B's normal.
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  bool cores_touch = false;  ///< true when the cores intersect (normal from the fallback)
};

/// Distance between primitive a at pose_a and primitive b at pose_b (body poses in the world).
PrimitiveDistance primitiveDistance(const Primitive& a, const Eigen::Isometry3d& pose_a,
                                    const Primitive& b, const Eigen::Isometry3d& pose_b);

/// Closest points of segments [p0, p1] and [q0, q1]: parameters s, t in [0, 1] of the points
/// p0 + s (p1 - p0) and q0 + t (q1 - q0). Robust for degenerate and parallel segments.
void closestSegmentParameters(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                              const Eigen::Vector3d& q0, const Eigen::Vector3d& q1, double& s,
                              double& t);

}  // namespace taskmap
