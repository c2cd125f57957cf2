#pragma once
// Private to validate: the hand's own dynamics in the hold test's scene (mjcf_model.cpp), where
// its model states them (HandModel::dynamics(), an MJCF hand's masses, servos, damping, contact
// parameters); the protocol's values where it is silent; and the record of which were used
// (the map's /validation params, key "hand_dynamics"). docs/VALIDATION.md, "A hand's own
// dynamics".
#include <string>

#include "taskmap/hands/hand_model.hpp"
#include "taskmap/validate/hold_test.hpp"

namespace taskmap::detail {

/// How many of each quantity the scene took from the hand's model (the rest: the protocol).
struct StatedUse {
  bool on = false;             ///< the model states dynamics and options.stated_dynamics is true
  int links = 0, inertia = 0;  ///< moving links; links whose mass and inertia are the model's
  int joints = 0, damping = 0, armature = 0, frictionloss = 0, stiffness = 0;  ///< movable joints
  int actuated = 0, kp = 0, kv = 0, ctrlrange = 0, forcerange = 0;             ///< actuated joints
  int couplings = 0, coupling_solref = 0, coupling_solimp = 0;                 ///< mimic joints
  int shapes = 0, friction = 0, solref = 0, solimp = 0;                        ///< collision shapes
  /// JSON of this record: {"source", "used", per quantity {"model": n, "of": m}, ...}.
  std::string json(const HandModel& hand) const;
};

/// True when the scene uses the hand's stated dynamics (an MJCF hand, option on).
bool usesStated(const HandModel& hand, const HoldTestOptions& options);

/// The <inertial> of moving link l from the model when it states a positive mass (pos and
/// fullinertia in the link frame), "" otherwise (then the protocol's).
std::string statedInertial(const HandModel& hand, int l, StatedUse* use);

/// Joint attributes damping, armature (stated, else the given protocol values), frictionloss,
/// stiffness and springref (when stated) of joint j.
std::string statedJoint(const HandModel& hand, int j, double damping, double armature,
                        StatedUse* use);

/// The actuator of actuated joint `joint` (index into joints()): the model's servo gains and
/// ranges where stated, else kp, the joint's limits and `limit` (infinity: no force limit).
std::string statedActuator(const HandModel& hand, const std::string& name,
                           const std::string& joint_xml_name, int joint, double kp, double limit,
                           StatedUse* use);

/// Extra attributes of the equality coupling mimic joint j (stated solref, solimp), "" when
/// silent (then `fallback`).
std::string statedCoupling(const HandModel& hand, int j, const std::string& fallback,
                           StatedUse* use);

/// Extra geom attributes of link l's shape k (friction, solref, solimp where stated; friction
/// components the model leaves unsaid are the protocol's `sliding` and `torsional`).
std::string statedContact(const HandModel& hand, int l, int k, double sliding, double torsional,
                          StatedUse* use);

}  // namespace taskmap::detail
