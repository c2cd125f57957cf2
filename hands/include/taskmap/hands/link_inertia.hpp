#pragma once
/// @file link_inertia.hpp
/// The mass model of a hand link for physics: what the hold test (validate) and the closing
/// check (grasp_sim) give each link (docs/VALIDATION.md, "The model").

#include <Eigen/Core>

#include "taskmap/hands/hand_model.hpp"

namespace taskmap {

/// A link's mass, centre of mass and inertia from its collision shapes.
struct LinkInertia {
  double mass = 0.0;                                 ///< kg, at least 1e-3
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< centre of mass, link frame, metres
  double inertia = 0.0;  ///< kg m^2 about the centre along every axis, at least 1e-8
};

/// Volume of a collision shape, m^3: exact for boxes, cylinders and spheres; half the bounding
/// box of a hull's points (an estimate for the mass).
double shapeVolume(const CollisionShape& shape);

/// `density` (kg/m^3) times the summed volume of the link's shapes (shapeVolume), at their
/// volume-weighted centre, with the inertia of a solid sphere reaching the farthest shape
/// (0.4 m r^2); mass at least 1e-3 kg and inertia at least 1e-8 kg m^2, so that links without
/// shapes stay simulable.
LinkInertia linkInertia(const HandLink& link, double density);

}  // namespace taskmap
