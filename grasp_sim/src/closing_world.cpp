// ClosingChecker::Model::run: one closing check in its own Bullet dynamics world
// (docs/METHOD.md §4d): the hand a fixed-base multibody with velocity motors that behave as the
// hold test's overdamped position servos, the object a free rigid body of convex pieces.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include "closing_model.hpp"
#include "collision_data.hpp"
#include "taskmap/core/error.hpp"

namespace taskmap {
namespace {

constexpr int kHandGroup = 1;
constexpr int kObjectGroup = 2;
constexpr double kSettled = 2e-4;  // m: overlap left when the quasi-static start ends

btQuaternion btQuat(const Eigen::Matrix3d& r) {
  const Eigen::Quaterniond q(r);
  return btQuaternion(q.x(), q.y(), q.z(), q.w());
}

Eigen::Isometry3d eigIso(const btTransform& t) {
  Eigen::Isometry3d e = Eigen::Isometry3d::Identity();
  const btMatrix3x3& b = t.getBasis();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) e.linear()(i, j) = b[i][j];
  e.translation() = eig(t.getOrigin());
  return e;
}

}  // namespace

/// A joint driven by a velocity motor: the overdamped servo of the hold test (gain kp, damping
/// c) moves at kp e / c and presses with at most kp |e| (and the jaw force).
struct ClosingDrive {
  int link = -1;   // multibody link
  int joint = -1;  // HandModel::joints() index
  double kp = 0.0, damping = 1.0, force_limit = 0.0;
  btMultiBodyJointMotor* motor = nullptr;
};

/// One trial's Bullet objects; everything is removed from the world before it is destroyed.
struct ClosingWorld {
  /// Small pools: Bullet's default pools (4096 manifolds and algorithms) are initialised element
  /// by element, megabytes per world; a check needs tens (the heap serves any excess).
  static btDefaultCollisionConstructionInfo poolSizes() {
    btDefaultCollisionConstructionInfo info;
    info.m_defaultMaxPersistentManifoldPoolSize = 64;
    info.m_defaultMaxCollisionAlgorithmPoolSize = 256;
    return info;
  }
  btDefaultCollisionConfiguration config{poolSizes()};
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btMultiBodyConstraintSolver solver;
  btMultiBodyDynamicsWorld world{&dispatcher, &broadphase, &solver, &config};
  std::unique_ptr<btMultiBody> hand;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> constraints;
  std::vector<ClosingDrive> drives;
  std::unique_ptr<btRigidBody> object;

  ~ClosingWorld() {
    if (object) world.removeRigidBody(object.get());
    for (auto& c : constraints) world.removeMultiBodyConstraint(c.get());
    for (auto& c : colliders) world.removeCollisionObject(c.get());
    if (hand) world.removeMultiBody(hand.get());
  }
};

namespace {

void addCollider(const ClosingLink& l, int index, const btTransform& at, ClosingWorld* w) {
  if (!l.shape) return;
  auto c = std::make_unique<btMultiBodyLinkCollider>(w->hand.get(), index);
  c->setCollisionShape(l.shape.get());
  c->setWorldTransform(at);
  c->setFriction(1.0);  // Bullet multiplies the two frictions: the object's is the check's
  c->setRestitution(0.0);
  w->world.addCollisionObject(c.get(), kHandGroup, kObjectGroup);
  if (index < 0)
    w->hand->setBaseCollider(c.get());
  else
    w->hand->getLink(index).m_collider = c.get();
  w->colliders.push_back(std::move(c));
}

/// The multibody at the palm pose with the URDF joint values `all` (HandModel::joints() order).
void buildHand(const ClosingChecker::Model& m, const Eigen::Isometry3d& root_pose,
               const Eigen::VectorXd& all, ClosingWorld* w) {
  const auto& hj = m.hand.joints();
  const int n = static_cast<int>(m.links.size());
  w->hand = std::make_unique<btMultiBody>(n, m.base.mass, btVector3(1, 1, 1) * m.base.inertia, true,
                                          false);
  btMultiBody& b = *w->hand;
  for (int i = 0; i < n; ++i) {
    const ClosingLink& l = m.links[static_cast<std::size_t>(i)];
    const HandJoint& j = hj[static_cast<std::size_t>(l.joint)];
    const btVector3 inertia = btVector3(1, 1, 1) * l.inertia;
    const btQuaternion to_this = btQuat(j.origin.linear()).inverse();
    const btVector3 pivot = bt(Eigen::Vector3d(j.origin.translation()));
    const btVector3 zero(0, 0, 0);
    if (j.type == JointType::kRevolute)
      b.setupRevolute(i, l.mass, inertia, l.parent, to_this, bt(j.axis), pivot, zero, true);
    else if (j.type == JointType::kPrismatic)
      b.setupPrismatic(i, l.mass, inertia, l.parent, to_this, bt(j.axis), pivot, zero, true);
    else
      b.setupFixed(i, l.mass, inertia, l.parent, to_this, pivot, zero);
  }
  b.finalizeMultiDof();
  b.setBaseWorldTransform(bt(root_pose));
  b.setLinearDamping(0.0);
  b.setAngularDamping(0.0);
  b.setHasSelfCollision(false);
  for (int i = 0; i < n; ++i) {
    const HandJoint& j = hj[static_cast<std::size_t>(m.links[static_cast<std::size_t>(i)].joint)];
    if (j.type != JointType::kFixed)
      b.setJointPos(i, all[m.links[static_cast<std::size_t>(i)].joint]);
  }
  w->world.addMultiBody(&b, kHandGroup, kObjectGroup);
  btAlignedObjectArray<btQuaternion> rot;
  btAlignedObjectArray<btVector3> pos;
  b.forwardKinematics(rot, pos);
  addCollider(m.base, -1, bt(root_pose), w);
  for (int i = 0; i < n; ++i)
    addCollider(m.links[static_cast<std::size_t>(i)], i, b.getLink(i).m_cachedWorldTransform, w);
  b.updateCollisionObjectWorldTransforms(rot, pos);
}

/// URDF joint targets for actuated values q clamped to their limits, mimic joints following
/// their drivers (as HandModel::linkPoses places them, even past their own limits).
Eigen::VectorXd jointTargets(const HandModel& hand, const Eigen::VectorXd& q) {
  return hand.allJointValues(q.cwiseMax(hand.lowerLimits()).cwiseMin(hand.upperLimits()));
}

/// Limits of URDF joint j: its own, widened for a mimic joint to the image of its driver's.
std::pair<double, double> jointLimits(const HandModel& hand, const HandJoint& j) {
  double lo = j.lower, hi = j.upper;
  if (j.driver >= 0 && j.mimic) {
    const double a = j.multiplier * hand.lowerLimits()[j.driver] + j.offset;
    const double b = j.multiplier * hand.upperLimits()[j.driver] + j.offset;
    lo = std::min({lo, a, b});
    hi = std::max({hi, a, b});
  }
  return {lo, hi};
}

void addDrives(const ClosingChecker::Model& m, ClosingWorld* w) {
  const ClosingCheckOptions& o = m.options;
  for (int i = 0; i < static_cast<int>(m.links.size()); ++i) {
    const int ji = m.links[static_cast<std::size_t>(i)].joint;
    const HandJoint& j = m.hand.joints()[static_cast<std::size_t>(ji)];
    if (j.type == JointType::kFixed || j.driver < 0) continue;
    const bool slide = j.type == JointType::kPrismatic;
    auto motor = std::make_unique<btMultiBodyJointMotor>(w->hand.get(), i, 0, 0.0, 0.0);
    const auto [lower, upper] = jointLimits(m.hand, j);
    auto limit = std::make_unique<btMultiBodyJointLimitConstraint>(w->hand.get(), i, lower, upper);
    ClosingDrive d;
    d.link = i;
    d.joint = ji;
    d.kp = m.drives[static_cast<std::size_t>(ji)].kp;
    d.damping = slide ? o.damping_prismatic : o.damping_revolute;
    d.force_limit = m.drives[static_cast<std::size_t>(ji)].limit;
    d.motor = motor.get();
    w->world.addMultiBodyConstraint(motor.get());
    w->world.addMultiBodyConstraint(limit.get());
    w->constraints.push_back(std::move(motor));
    w->constraints.push_back(std::move(limit));
    w->drives.push_back(d);
  }
}

void addObject(const ClosingChecker::Model& m, ClosingWorld* w) {
  const btVector3 inertia = bt(m.object_inertia);
  btRigidBody::btRigidBodyConstructionInfo info(m.options.object_mass, nullptr, m.object.get(),
                                                inertia);
  info.m_startWorldTransform = bt(m.object_principal);
  info.m_friction = m.options.friction;
  info.m_restitution = 0.0;
  w->object = std::make_unique<btRigidBody>(info);
  // Bullet combines torsional friction as spin_a friction_b + spin_b friction_a: the hand's
  // spinning friction 0 and its friction 1 leave the object's value.
  const bool jaw_value = m.jaws && m.options.jaws.torsional_friction >= 0.0;
  w->object->setSpinningFriction(jaw_value ? m.options.jaws.torsional_friction
                                           : m.options.torsional_friction);
  w->object->setActivationState(DISABLE_DEACTIVATION);
  w->world.addRigidBody(w->object.get(), kObjectGroup, kHandGroup);
}

/// Deepest hand-object overlap in the current state, metres.
double deepestOverlap(ClosingWorld* w) {
  w->world.performDiscreteCollisionDetection();
  double deepest = 0.0;
  for (int k = 0; k < w->dispatcher.getNumManifolds(); ++k) {
    const btPersistentManifold* pm = w->dispatcher.getManifoldByIndexInternal(k);
    for (int c = 0; c < pm->getNumContacts(); ++c)
      deepest = std::max(deepest, -static_cast<double>(pm->getContactPoint(c).getDistance()));
  }
  return deepest;
}

/// The servo's velocity kp e / c, at most e / h: a step longer than the servo's time constant
/// c / kp (5 ms for the jaws) would otherwise carry the joint past its target (at h = 1 ms the
/// bound never binds).
void setDrives(const Eigen::VectorXd& target, double h, ClosingWorld* w) {
  for (const ClosingDrive& d : w->drives) {
    const double e = target[d.joint] - w->hand->getJointPos(d.link);
    d.motor->setVelocityTarget(h * d.kp <= d.damping ? d.kp * e / d.damping : e / h, 1.0);
    d.motor->setMaxAppliedImpulse(std::min(d.kp * std::abs(e), d.force_limit) * h);
  }
}

double placementError(const ClosingChecker::Model& m, const Eigen::Isometry3d& palm,
                      const Eigen::VectorXd& q, const ClosingWorld& w) {
  const std::vector<Eigen::Isometry3d> poses = m.hand.linkPoses(q);
  double worst = 0.0;
  for (std::size_t i = 0; i < m.links.size(); ++i) {
    const Eigen::Isometry3d want = palm * poses[static_cast<std::size_t>(m.links[i].link)];
    const Eigen::Isometry3d got =
        eigIso(w.hand->getLink(static_cast<int>(i)).m_cachedWorldTransform);
    worst = std::max({worst, (want.translation() - got.translation()).norm(),
                      0.05 * (want.linear() - got.linear()).norm()});
  }
  return worst;
}

/// Quasi-static start: the stored grasps press the palm (and pressed links) into the object by
/// the squeeze, and Bullet's velocity-level depenetration would launch the free object with
/// the velocity that removes the overlap (it has no spring-damper that stops it, as MuJoCo's
/// critically damped contacts do). So the overlap is removed first with the hand held at the
/// pregrasp and the object's velocity zeroed after every step: the object ends at rest, out of
/// the overlap (at most max_settle_steps steps).
void settle(const Eigen::VectorXd& target, double h, const ClosingCheckOptions& o, ClosingWorld* w,
            ClosingCheckResult* r) {
  w->world.getSolverInfo().m_erp2 = o.settle_erp;
  for (int s = 0; s < o.max_settle_steps; ++s) {
    if (deepestOverlap(w) < kSettled) break;
    setDrives(target, h, w);
    w->world.stepSimulation(h, 0, h);
    w->object->setLinearVelocity(btVector3(0, 0, 0));
    w->object->setAngularVelocity(btVector3(0, 0, 0));
    ++r->steps;
    ++r->settle_steps;
  }
  w->world.getSolverInfo().m_erp2 = o.contact_erp;
}

/// The object's motion from its start (the identity) into *r, and the verdict.
void measure(const btRigidBody& object, const Eigen::Isometry3d& principal,
             const ClosingCheckOptions& o, ClosingCheckResult* r) {
  const Eigen::Isometry3d moved = eigIso(object.getWorldTransform()) * principal.inverse();
  r->displacement = moved.translation();
  r->translation = r->displacement.norm();
  r->rotation = Eigen::AngleAxisd(moved.linear()).angle();
  r->unstable = !std::isfinite(r->translation) || !std::isfinite(r->rotation);
  r->holds = !r->unstable && r->translation < o.max_translation && r->rotation < o.max_rotation;
}

}  // namespace

namespace {

/// Whether the object moves slower than the rest speed (centre of mass, and turning times 5 cm).
bool atRest(const btRigidBody& object, double rest_speed) {
  return object.getLinearVelocity().length() < rest_speed &&
         object.getAngularVelocity().length() * 0.05 < rest_speed;
}

/// Whether the object, were the hand to let go now, would still stay within both thresholds
/// until the push ends `remaining` seconds (steps of h) later: its origin (`arm` metres from the
/// centre of mass) moving on with the current velocities and the push's acceleration a = F / m
/// as Bullet integrates it (v += a h, then x += v h: a T (T + h) / 2 over T), its rotation with
/// the current spin (docs/METHOD.md §4d, "Free-body bound").
bool staysWithin(const btRigidBody& object, double arm, double remaining, double h,
                 const ClosingCheckOptions& o, const ClosingCheckResult& r) {
  const double v = object.getLinearVelocity().length();
  const double w = object.getAngularVelocity().length();
  const double reach = r.translation + (v + w * arm) * remaining +
                       0.5 * (o.push_force / o.object_mass) * remaining * (remaining + h);
  return reach < o.max_translation && r.rotation + w * remaining < o.max_rotation;
}

}  // namespace

void ClosingChecker::Model::push(const Eigen::VectorXd& squeeze, double h, ClosingWorld* w,
                                 ClosingCheckResult* r) const {
  const Eigen::VectorXd target = jointTargets(hand, squeeze);
  const int steps = std::max(1, static_cast<int>(std::lround(options.push_duration / h)));
  const bool early = options.rest_speed > 0.0;  // verdict after every step, rest ends a push
  for (const int dir : options.push_order) {
    btVector3 f(0, 0, 0);
    f[dir / 2] = dir % 2 == 0 ? -options.push_force : options.push_force;
    int resting = 0;
    const Eigen::Vector3d from = r->displacement;  // where this push starts
    for (int s = 0; s < steps; ++s) {
      setDrives(target, h, w);
      w->object->applyCentralForce(f);  // cleared by every step
      w->world.stepSimulation(h, 0, h);
      ++r->steps;
      ++r->push_steps[static_cast<std::size_t>(dir)];
      if (!early) continue;
      measure(*w->object, object_principal, options, r);
      if (!r->holds) break;
      resting = atRest(*w->object, options.rest_speed) ? resting + 1 : 0;
      if (resting >= options.rest_steps) break;
      const bool creeping =
          options.push_bound_creep > 0.0 &&
          (r->displacement - from).norm() >= options.push_bound_creep * (s + 1) * h;
      if (options.push_free_bound && !creeping &&
          staysWithin(*w->object, object_principal.translation().norm(), (steps - 1 - s) * h, h,
                      options, *r))
        break;
    }
    measure(*w->object, object_principal, options, r);
    if (!r->holds) {
      r->failed_push = dir;
      return;
    }
  }
}

ClosingCheckResult ClosingChecker::Model::run(const Pose& palm_pose,
                                              const Eigen::VectorXd& joints) const {
  const ClosingCheckOptions& o = options;
  const Eigen::VectorXd pre = hand.preshape();
  const Eigen::VectorXd pregrasp = pre + o.pregrasp_fraction * (joints - pre);
  const Eigen::VectorXd squeeze = pre + o.squeeze_fraction * (joints - pre);
  const Eigen::Isometry3d palm = palm_pose.toIsometry();
  ClosingWorld w;
  w.world.setGravity(btVector3(0, 0, 0));
  btContactSolverInfo& solver = w.world.getSolverInfo();
  solver.m_numIterations =
      jaws && o.jaws.solver_iterations > 0 ? o.jaws.solver_iterations : o.solver_iterations;
  if (o.warm_start_drives || (jaws && o.jaws.warm_start_drives))
    solver.m_solverMode |= SOLVER_USE_ARTICULATED_WARMSTARTING;
  w.world.getSolverInfo().m_erp2 = o.contact_erp;
  buildHand(*this, palm * hand.rootToPalm().inverse(), jointTargets(hand, pregrasp), &w);
  addDrives(*this, &w);
  addObject(*this, &w);
  ClosingCheckResult r;
  r.placement_error = placementError(*this, palm, pregrasp, w);
  r.initial_penetration = deepestOverlap(&w);
  if (r.initial_penetration > o.max_penetration) return r;
  const double h = o.timestep / o.substeps;
  settle(jointTargets(hand, pregrasp), h, o, &w, &r);
  const int steps =
      std::max(1, static_cast<int>(std::lround(0.5 * o.closing_time / o.interpolation_stages / h)));
  const Eigen::VectorXd* path[3] = {&pregrasp, &joints, &squeeze};
  for (int phase = 0; phase < 2; ++phase) {
    const Eigen::VectorXd& from = *path[phase];
    const Eigen::VectorXd& to = *path[phase + 1];
    for (int k = 1; k <= o.interpolation_stages; ++k) {
      const double t = static_cast<double>(k) / o.interpolation_stages;
      const Eigen::VectorXd target = jointTargets(hand, from + t * (to - from));
      for (int s = 0; s < steps; ++s) {
        setDrives(target, h, &w);
        w.world.stepSimulation(h, 0, h);
        ++r.steps;
        ++r.closing_steps;
      }
      measure(*w.object, object_principal, o, &r);
      if (!r.holds) return r;  // already moved too far (or diverged): no need to go on
    }
  }
  if (o.mode == ClosingCheckMode::kPushes) push(squeeze, h, &w, &r);
  return r;
}

}  // namespace taskmap
