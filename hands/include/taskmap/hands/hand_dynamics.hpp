#pragma once
/// @file hand_dynamics.hpp
/// What a hand model states about its own dynamics, as plain data: the values an MJCF hand gives
/// (masses and inertias, joint damping, armature and friction loss, position-actuator gains and
/// ranges, geom friction and contact softness, coupling softness, contact exclusions). Every
/// value is optional: empty where the model is silent (the validator then uses its protocol's
/// value, docs/VALIDATION.md). A URDF hand states none of them here. Units: SI (metres,
/// radians, kilograms, newtons, seconds); angles in radians whatever the model file used.

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "taskmap/hands/urdf_model.hpp"

namespace taskmap {

/// A joint's stated dynamics (MJCF <joint> attributes, from the element or its default class).
struct JointDynamics {
  std::optional<double> damping;       ///< N m s / rad (hinge) or N s / m (slide)
  std::optional<double> armature;      ///< kg m^2 (hinge) or kg (slide): reflected rotor inertia
  std::optional<double> frictionloss;  ///< N m (hinge) or N (slide): dry friction
  std::optional<double> stiffness;     ///< N m / rad or N / m: spring toward springref
  std::optional<double> springref;     ///< radians or metres: the spring's rest value
  /// Softness of the joint coupling that makes this a mimic joint (MJCF <equality><joint> solref:
  /// time constant s, damping ratio), when the model states it.
  std::optional<std::array<double, 2>> coupling_solref;
  /// Its impedance (MJCF solimp: dmin, dmax, width m, midpoint, power), when stated.
  std::optional<std::array<double, 5>> coupling_solimp;
};

/// The position servo a model states for an actuated joint, in the joint's own units: an MJCF
/// <position> (or <general> with an affine bias that is a position servo) on the joint, or on a
/// fixed tendon whose coupling made the joint the driver (gear and tendon coefficients applied:
/// a gain kp on a length L = s q acts as kp s^2 on q).
struct ActuatorDynamics {
  std::string name;          ///< the model's actuator name ("" when unnamed)
  std::optional<double> kp;  ///< N m / rad or N / m: position gain
  std::optional<double> kv;  ///< N m s / rad or N s / m: velocity gain (damping of the servo)
  std::optional<std::array<double, 2>> ctrlrange;   ///< target range, radians or metres
  std::optional<std::array<double, 2>> forcerange;  ///< N m or N: force limits of the servo
  /// Why the model's actuator gives no servo to use ("" when it does): e.g. a <motor>.
  std::string unused;
};

/// A collision shape's stated contact parameters (MJCF geom friction, solref, solimp).
struct ShapeContact {
  std::optional<double> sliding;                ///< sliding friction coefficient
  std::optional<double> torsional;              ///< torsional friction, metres
  std::optional<double> rolling;                ///< rolling friction, metres
  std::optional<std::array<double, 2>> solref;  ///< time constant s, damping ratio
  std::optional<std::array<double, 5>> solimp;  ///< dmin, dmax, width m, midpoint, power
};

/// What a hand model states about its dynamics (HandModel::dynamics()).
struct HandDynamics {
  /// "MJCF" when the model is an MJCF file (then every vector below has its full size), "" for a
  /// URDF (every vector empty: nothing stated).
  std::string source;
  /// Per link (HandModel::links() order): mass, centre of mass and inertia, when stated.
  std::vector<std::optional<UrdfInertial>> links;
  /// Per joint (HandModel::joints() order).
  std::vector<JointDynamics> joints;
  /// Per joint (HandModel::joints() order): the servo driving it, for actuated joints that have
  /// one.
  std::vector<std::optional<ActuatorDynamics>> actuators;
  /// Per link, per collision shape (HandLink::shapes order; one shape per collision geom).
  std::vector<std::vector<ShapeContact>> shapes;
  /// Link pairs (indices into HandModel::links(), smaller first) that never collide with each
  /// other (MJCF <contact><exclude>).
  std::vector<std::array<int, 2>> excluded_pairs;
};

}  // namespace taskmap
