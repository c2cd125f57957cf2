// The closing check (grasp_sim/closing_check.hpp): closing with the object free to move.
// Oracles: a one-jaw grasp of an offset box must push the box over by its offset (closed
// form), the centred grasp of the same box must leave it in place; a barrett grasp of a
// cylinder that the physics hold test (MuJoCo, validate) holds passes; the verdict is a pure
// function of the grasp (threads, repeats); options are validated with messages naming them.
#include "taskmap/grasp_sim/closing_check.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <thread>
#include <vector>

#include "error_matchers.hpp"
#include "grasp_fixtures.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/grasp_sim/grasp_simulator.hpp"
#include "taskmap/validate/hold_test.hpp"
#include "test_meshes.hpp"

namespace taskmap {
namespace {

using testing::fromAbove;

ClosingCheckOptions closingOn() {
  ClosingCheckOptions o;
  o.mode = ClosingCheckMode::kClosing;
  return o;
}

HandModel pandaMimic() {
  return HandModel::load(testing::testHandPath("panda_mimic"));
}

TEST(ClosingCheck, ModeNamesAndOptionErrors) {
  EXPECT_STREQ(toString(ClosingCheckMode::kOff), "off");
  EXPECT_STREQ(toString(ClosingCheckMode::kClosing), "closing");
  EXPECT_STREQ(toString(ClosingCheckMode::kPushes), "pushes");
  EXPECT_EQ(closingCheckModeFromString("pushes"), ClosingCheckMode::kPushes);
  EXPECT_TRUE(testing::throwsError([] { closingCheckModeFromString("on"); },
                                   {"\"off\", \"closing\" or \"pushes\"", "\"on\""}));
  ClosingCheckOptions o;
  EXPECT_NO_THROW(o.validate());
  o.object_mass = 0.0;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"object_mass", "positive", "kg"}));
  o = ClosingCheckOptions();
  o.contact_erp = 1.5;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"contact_erp", "(0, 1]"}));
  o = ClosingCheckOptions();
  o.squeeze_fraction = 0.5;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"squeeze_fraction", "[1, 2]"}));
  o = ClosingCheckOptions();
  o.substeps = 0;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"substeps", ">= 1"}));
  o = ClosingCheckOptions();
  o.object_max_pieces = 65;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"object_max_pieces", "[1, 64]"}));
  o = ClosingCheckOptions();
  o.rest_speed = -0.001;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"rest_speed", ">= 0", "m/s"}));
  o = ClosingCheckOptions();
  o.rest_steps = 0;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"rest_steps", ">= 1"}));
  o = ClosingCheckOptions();
  o.push_order = {0, 1, 2, 3, 4, 4};
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"push_order", "0..5", "once"}));
  o = ClosingCheckOptions();
  o.push_bound_creep = -1.0;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"push_bound_creep", ">= 0", "m/s"}));
  o = ClosingCheckOptions();
  o.torsional_friction = -0.01;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"torsional_friction", ">= 0", "m"}));
  o = ClosingCheckOptions();
  o.jaws.solver_iterations = -1;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"jaws.solver_iterations", ">= 0"}));
  o = ClosingCheckOptions();
  o.timestep = 0.2;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"timestep", "closing_time"}));
  // The constructor validates, and check() names a joint count that does not fit.
  const ObjectModel box = ObjectModel::fromMesh(testing::makeBox(0.04, 0.03, 0.1), "box");
  o = closingOn();
  o.max_rotation = -1.0;
  EXPECT_TRUE(
      testing::throwsError([&] { ClosingChecker(box, pandaMimic(), o); }, {"max_rotation"}));
  const ClosingChecker checker(box, pandaMimic(), closingOn());
  EXPECT_TRUE(testing::throwsError(
      [&] { checker.check(fromAbove(Eigen::Vector3d::Zero()), Eigen::VectorXd::Zero(3)); },
      {"3 joint values", "panda", "1 actuated"}));
}

// A 4 cm box 15 mm off the centre of mimic jaws. Without centring the kinematic closing stops
// at the first touch (one jaw, the other 30 mm from the box); closing that grasp with the box
// free, the touching jaw drives on to the squeeze target (10 % past the grasp) and pushes the
// box along the closing direction (object x) at least that far, nothing stopping it. The
// centred grasp of the same trial (both jaws) keeps it within a few millimetres.
TEST(ClosingCheck, OneJawPushMovesTheBoxByItsOffset) {
  const double off = 0.015;
  const TriangleMesh mesh = testing::makeBox(0.04, 0.03, 0.10);
  const ObjectModel box = ObjectModel::fromMesh(mesh, "box");
  const HandModel hand = pandaMimic();
  GraspSimOptions stiff;
  stiff.centre_coupled = false;
  const GraspResult one =
      GraspSimulator(mesh, hand, stiff).simulate(fromAbove(Eigen::Vector3d(off, 0.0, -0.01)));
  ASSERT_EQ(one.status, GraspStatus::kOk) << one.message;
  ASSERT_EQ(one.fingers_in_contact.size(), 1u);
  const GraspResult both =
      GraspSimulator(mesh, hand).simulate(fromAbove(Eigen::Vector3d(off, 0.0, -0.01)));
  ASSERT_EQ(both.status, GraspStatus::kOk) << both.message;
  ASSERT_EQ(both.fingers_in_contact.size(), 2u);

  ClosingCheckOptions loose = closingOn();
  loose.max_translation = 0.05;  // see the whole push
  const ClosingChecker measure(box, hand, loose);
  const ClosingCheckResult pushed = measure.check(one.pose, one.joints);
  EXPECT_LT(pushed.placement_error, 1e-9);
  const double travel = 0.1 * std::abs(one.joints[0] - hand.preshape()[0]);  // grasp to squeeze
  EXPECT_GT(std::abs(pushed.displacement.x()), travel);
  EXPECT_GT(std::abs(pushed.displacement.x()), pushed.displacement.tail<2>().norm());
  const ClosingChecker checker(box, hand, closingOn());
  const ClosingCheckResult refused = checker.check(one.pose, one.joints);
  EXPECT_FALSE(refused.holds);
  EXPECT_GE(refused.translation, checker.options().max_translation);
  const ClosingCheckResult held = checker.check(both.pose, both.joints);
  EXPECT_TRUE(held.holds) << held.translation << " m, " << held.rotation << " rad";
  EXPECT_LT(held.translation, 0.005);
}

/// The first trials of barrett on a lying cylinder that close with all three fingers.
std::vector<GraspResult> barrettCylinderGrasps(const TriangleMesh& mesh, int n) {
  const HandModel hand = testing::referenceHand("barrett");
  const GraspSimulator sim(mesh, hand);
  std::vector<GraspResult> out;
  for (const Pose& p : testing::randomPoses(400, Eigen::Vector3d(-0.03, -0.03, -0.03),
                                            Eigen::Vector3d(0.03, 0.03, 0.03), 7)) {
    GraspResult g = sim.simulate(p);
    if (g.status == GraspStatus::kOk && g.fingers_in_contact.size() == 3 && g.palm_contact)
      out.push_back(std::move(g));
    if (static_cast<int>(out.size()) == n) break;
  }
  return out;
}

// A barrett grasp of a cylinder that the physics hold test holds firmly (the object moves less
// than 5 mm under every push) passes the check, which keeps the object within 2 mm.
TEST(ClosingCheck, BarrettGraspThatHoldsInPhysicsPasses) {
  const TriangleMesh mesh = testing::makeCylinder(0.035, 0.16, 48, 0);
  const ObjectModel cylinder = ObjectModel::fromMesh(mesh, "cylinder");
  const HandModel hand = testing::referenceHand("barrett");
  const std::vector<GraspResult> grasps = barrettCylinderGrasps(mesh, 8);
  ASSERT_FALSE(grasps.empty());
  HoldTestOptions protocol;
  protocol.settle_stop = false;  // the largest displacement over the whole pushes
  const HoldTester validator(hand, cylinder, protocol);
  const ClosingChecker checker(cylinder, hand, closingOn());
  int firm = 0;
  for (const GraspResult& g : grasps) {
    const HoldResult h = validator.test(g.pose, g.joints);
    if (!h.holds || h.max_translation > 0.005) continue;
    ++firm;
    const ClosingCheckResult r = checker.check(g.pose, g.joints);
    EXPECT_TRUE(r.holds) << r.translation << " m, " << r.rotation << " rad";
    EXPECT_LT(r.translation, 0.002);
    EXPECT_LT(r.placement_error, 1e-9);
  }
  EXPECT_GE(firm, 1) << "no grasp held firmly in the hold test";
}

// The early verdict of the pushes (rest_speed > 0). Barrett grasps of a cylinder that hold
// every push of the full check: with the early end each push stops once the object rests, so
// the check takes fewer steps (at least rest_steps per push) for the same verdict and nearly
// the same final place. Jaws pressing with 0.4 N on a box cannot resist the 1 N pushes
// (friction 0.6 x 2 x 0.4 N = 0.48 N): the same push fails in both, and the early verdict stops
// at the first step past a threshold, so it takes fewer steps and the object moved no further
// than in the full push.
TEST(ClosingCheck, EarlyVerdictEndsPushesAtRestOrAtTheThreshold) {
  ClosingCheckOptions full = closingOn();
  full.mode = ClosingCheckMode::kPushes;
  full.timestep = 0.004;
  full.substeps = 1;
  full.push_duration = 0.2;
  full.rest_speed = 0.0;
  ClosingCheckOptions early = full;
  early.rest_speed = 0.005;
  const int push_steps = 6 * 50;  // 0.2 s of 4 ms steps
  {
    const TriangleMesh mesh = testing::makeCylinder(0.035, 0.16, 48, 0);
    const ObjectModel cylinder = ObjectModel::fromMesh(mesh, "cylinder");
    const HandModel hand = testing::referenceHand("barrett");
    const ClosingChecker checker_full(cylinder, hand, full), checker_early(cylinder, hand, early);
    int held = 0;
    for (const GraspResult& g : barrettCylinderGrasps(mesh, 3)) {
      const ClosingCheckResult a = checker_full.check(g.pose, g.joints);
      if (!a.holds) continue;
      ++held;
      const ClosingCheckResult b = checker_early.check(g.pose, g.joints);
      EXPECT_TRUE(b.holds) << b.translation << " m, " << b.rotation << " rad";
      EXPECT_LT(b.steps, a.steps);
      EXPECT_GE(b.steps, a.steps - push_steps + 6 * early.rest_steps);
      EXPECT_LT((a.displacement - b.displacement).norm(), 0.002);
    }
    EXPECT_GE(held, 1) << "no barrett grasp held the full pushes";
    // The early-verdict settings bound the steps: at most 10 settle steps, 2 x 5 closing stages
    // of one 8 ms step, six pushes of at most round(0.05 s / 8 ms) = 6 steps.
    const ClosingCheckOptions fast = ClosingCheckOptions::earlyVerdict();
    EXPECT_NO_THROW(fast.validate());
    EXPECT_EQ(fast.mode, ClosingCheckMode::kPushes);
    const ClosingChecker checker_fast(cylinder, hand, fast);
    for (const GraspResult& g : barrettCylinderGrasps(mesh, 3)) {
      const ClosingCheckResult r = checker_fast.check(g.pose, g.joints);
      EXPECT_GT(r.steps, 10);
      EXPECT_LE(r.steps, 10 + 10 + 6 * 6);
    }
  }
  const TriangleMesh mesh = testing::makeBox(0.04, 0.03, 0.10);
  const ObjectModel box = ObjectModel::fromMesh(mesh, "box");
  const HandModel hand = pandaMimic();
  const GraspResult g =
      GraspSimulator(mesh, hand).simulate(fromAbove(Eigen::Vector3d(0.0, 0.0, -0.01)));
  ASSERT_EQ(g.status, GraspStatus::kOk) << g.message;
  full.jaw_force = 0.4;
  early.jaw_force = 0.4;
  const ClosingCheckResult c = ClosingChecker(box, hand, full).check(g.pose, g.joints);
  const ClosingCheckResult d = ClosingChecker(box, hand, early).check(g.pose, g.joints);
  ASSERT_FALSE(c.holds);
  ASSERT_FALSE(d.holds);
  ASSERT_GE(c.failed_push, 0) << "the weak grasp must fail under a push, not while closing";
  EXPECT_EQ(d.failed_push, c.failed_push);
  EXPECT_TRUE(d.translation >= early.max_translation || d.rotation >= early.max_rotation);
  EXPECT_LE(d.translation, c.translation + 1e-3);
  EXPECT_LT(d.steps, c.steps);
}

// A box the hand never touches (the palm 0.5 m above it): the closing leaves it in place and
// each push moves it freely. Bullet's integrator (v += a h, then x += v h) gives after n steps
// of a push x = a h^2 n (n + 1) / 2 with a = F / m = 10 m/s^2 and h = 8 ms: 6 steps (0.05 s)
// move it 21 a h^2 = 13.44 mm. With the 1 cm threshold the first push (-x) fails at its sixth
// step, with and without the free-body bound (what the bound predicts is exactly that motion,
// never below the threshold before it is crossed), bit for bit; in another push order the first
// push fails the same way along its own axis. With a 5 cm threshold every push passes: without
// the bound each runs its 6 steps (the next push starting with the velocity the last one left:
// -x then +x ends at 21 + 15 = 36 a h^2 along x, and so on; 36 a h^2 sqrt(3) in all), with it
// each push ends after one step, once the prediction stays below 5 cm (a h^2 along each axis).
TEST(ClosingCheck, FreeBodyBoundEndsOnlyPushesThatCannotFail) {
  const ObjectModel box = ObjectModel::fromMesh(testing::makeBox(0.04, 0.04, 0.04), "box");
  const HandModel hand = testing::referenceHand("barrett");
  ClosingCheckOptions plain = ClosingCheckOptions::earlyVerdict();
  plain.push_free_bound = false;
  ClosingCheckOptions bound = plain;
  bound.push_free_bound = true;
  const Pose far = fromAbove(Eigen::Vector3d(0.0, 0.0, 0.5));
  const Eigen::VectorXd q = hand.preshape();
  const double ah2 = 10.0 * 0.008 * 0.008;  // m: a h^2
  const ClosingCheckResult a = ClosingChecker(box, hand, plain).check(far, q);
  const ClosingCheckResult b = ClosingChecker(box, hand, bound).check(far, q);
  for (const ClosingCheckResult& r : {a, b}) {
    EXPECT_FALSE(r.holds);
    EXPECT_EQ(r.failed_push, 0);
    EXPECT_EQ(r.push_steps[0], 6);
    EXPECT_EQ(r.steps, r.settle_steps + r.closing_steps + 6);
    EXPECT_NEAR(r.displacement.x(), -21.0 * ah2, 1e-9);
    EXPECT_NEAR(r.displacement.tail<2>().norm(), 0.0, 1e-9);
  }
  EXPECT_EQ(a.translation, b.translation);
  EXPECT_EQ(a.steps, b.steps);
  ClosingCheckOptions reversed = bound;
  reversed.push_order = {5, 4, 3, 2, 1, 0};
  const ClosingCheckResult c = ClosingChecker(box, hand, reversed).check(far, q);
  EXPECT_EQ(c.failed_push, 5);
  EXPECT_EQ(c.push_steps[5], 6);
  EXPECT_EQ(c.push_steps[0], 0);
  EXPECT_NEAR(c.displacement.z(), 21.0 * ah2, 1e-9);

  plain.max_translation = bound.max_translation = 0.05;
  const ClosingCheckResult d = ClosingChecker(box, hand, plain).check(far, q);
  const ClosingCheckResult e = ClosingChecker(box, hand, bound).check(far, q);
  EXPECT_TRUE(d.holds);
  EXPECT_TRUE(e.holds);
  EXPECT_EQ(d.push_steps, (std::array<int, 6>{6, 6, 6, 6, 6, 6}));
  EXPECT_EQ(e.push_steps, (std::array<int, 6>{1, 1, 1, 1, 1, 1}));
  EXPECT_NEAR((d.displacement + Eigen::Vector3d::Constant(36.0 * ah2)).norm(), 0.0, 1e-9);
  EXPECT_NEAR((e.displacement + Eigen::Vector3d::Constant(ah2)).norm(), 0.0, 1e-9);
  // With the creep condition (push_bound_creep 2.5 cm/s) the bound waits for an object that
  // moves slower than that since its push began: the free box moves a h^2 = 0.64 mm in its first
  // 8 ms step (8 cm/s) and faster after, so every push runs to its end, bit for bit as without
  // the bound.
  bound.push_bound_creep = 0.025;
  const ClosingCheckResult g = ClosingChecker(box, hand, bound).check(far, q);
  EXPECT_TRUE(g.holds);
  EXPECT_EQ(g.push_steps, d.push_steps);
  EXPECT_EQ(g.displacement, d.displacement);
  EXPECT_EQ(g.steps, d.steps);
}

// The jaws' settings of the early verdict (ClosingCheckOptions::jaws: 20 solver iterations,
// torsional friction 0.02 m, warm-started drives; what they change on jaw grasps is tested in
// closing_check_build_test). A hand without a driven prismatic joint ignores them: the
// barrett's numbers are the same bit for bit with and without.
TEST(ClosingCheck, JawSettingsLeaveOtherHandsAlone) {
  const ClosingCheckOptions early = ClosingCheckOptions::earlyVerdict();
  EXPECT_EQ(early.jaws.solver_iterations, 20);
  EXPECT_EQ(early.jaws.torsional_friction, 0.02);
  EXPECT_TRUE(early.jaws.warm_start_drives);
  ClosingCheckOptions plain = early;
  plain.jaws = ClosingCheckOptions::Jaws();
  const TriangleMesh cyl = testing::makeCylinder(0.035, 0.16, 48, 0);
  const ObjectModel cylinder = ObjectModel::fromMesh(cyl, "cylinder");
  const HandModel barrett = testing::referenceHand("barrett");
  const ClosingChecker with_jaws(cylinder, barrett, early), without(cylinder, barrett, plain);
  const std::vector<GraspResult> grasps = barrettCylinderGrasps(cyl, 3);
  ASSERT_EQ(grasps.size(), 3u);
  for (const GraspResult& b : grasps) {
    const ClosingCheckResult x = with_jaws.check(b.pose, b.joints);
    const ClosingCheckResult y = without.check(b.pose, b.joints);
    EXPECT_EQ(x.holds, y.holds);
    EXPECT_EQ(x.translation, y.translation);
    EXPECT_EQ(x.rotation, y.rotation);
    EXPECT_EQ(x.steps, y.steps);
    EXPECT_EQ(x.failed_push, y.failed_push);
  }
}

// A gripper driven by one revolute joint (tests/data/hands/knuckle_jaw, as a Robotiq 2F-85's
// linkage) presses each tip with the jaw force, as in the hold test (hands' jointDrives): its
// centred grasp of a box, which the hold test holds, passes the early check (the object moves
// under 5 mm). With the option off its joints servo with kp_revolute = 5 N m/rad: the squeeze
// past the grasp (a tenth of its 0.6 rad closing) presses each tip with under 2 N over the
// 0.04 m knuckle, and a 1 N push moves the box out (measured: the fifth push, 1.1 cm).
TEST(ClosingCheck, ARevoluteGripperPressesWithTheJawForce) {
  const TriangleMesh mesh = testing::makeBox(0.04, 0.03, 0.10);
  const ObjectModel box = ObjectModel::fromMesh(mesh, "box");
  const HandModel hand = HandModel::load(testing::testHandPath("knuckle_jaw"));
  const GraspResult g =
      GraspSimulator(mesh, hand).simulate(fromAbove(Eigen::Vector3d(0.0, 0.0, -0.01)));
  ASSERT_EQ(g.status, GraspStatus::kOk) << g.message;
  ASSERT_EQ(g.fingers_in_contact.size(), 2u);
  // The oracle: the physics hold test (MuJoCo, the validator's drive) holds this grasp.
  const HoldResult physics = HoldTester(hand, box).test(g.pose, g.joints);
  ASSERT_TRUE(physics.holds) << physics.max_translation << " m, " << physics.max_rotation << " rad";
  const ClosingCheckOptions o = ClosingCheckOptions::earlyVerdict();
  ASSERT_TRUE(o.revolute_gripper_force);
  const ClosingCheckResult pressed = ClosingChecker(box, hand, o).check(g.pose, g.joints);
  EXPECT_TRUE(pressed.holds) << pressed.translation << " m, " << pressed.rotation << " rad";
  EXPECT_LT(pressed.translation, 0.005);
  ClosingCheckOptions off = o;
  off.revolute_gripper_force = false;
  const ClosingCheckResult plain = ClosingChecker(box, hand, off).check(g.pose, g.joints);
  EXPECT_FALSE(plain.holds);
  EXPECT_GE(plain.failed_push, 0) << "the light grip fails under a push, not while closing";
}

// Each check builds its own world: the same grasp gives the same numbers, bit for bit, repeated
// and from several threads at once (also in the push mode).
TEST(ClosingCheck, VerdictIsAPureFunctionOfTheGrasp) {
  const TriangleMesh mesh = testing::makeCylinder(0.035, 0.16, 48, 0);
  const ObjectModel cylinder = ObjectModel::fromMesh(mesh, "cylinder");
  const HandModel hand = testing::referenceHand("barrett");
  const std::vector<GraspResult> grasps = barrettCylinderGrasps(mesh, 3);
  ASSERT_EQ(grasps.size(), 3u);
  ClosingCheckOptions o = closingOn();
  o.mode = ClosingCheckMode::kPushes;
  o.push_duration = 0.05;
  const ClosingChecker checker(cylinder, hand, o);
  std::vector<ClosingCheckResult> first;
  for (const GraspResult& g : grasps) first.push_back(checker.check(g.pose, g.joints));
  std::vector<std::vector<ClosingCheckResult>> par(3);
  std::vector<std::thread> threads;
  for (int t = 0; t < 3; ++t)
    threads.emplace_back([&, t] {
      for (std::size_t i = 0; i < grasps.size(); ++i) {
        const std::size_t k = (i + static_cast<std::size_t>(t)) % grasps.size();
        par[static_cast<std::size_t>(t)].resize(grasps.size());
        par[static_cast<std::size_t>(t)][k] = checker.check(grasps[k].pose, grasps[k].joints);
      }
    });
  for (auto& th : threads) th.join();
  for (const auto& run : par)
    for (std::size_t i = 0; i < grasps.size(); ++i) {
      EXPECT_EQ(run[i].holds, first[i].holds);
      EXPECT_EQ(run[i].translation, first[i].translation);
      EXPECT_EQ(run[i].rotation, first[i].rotation);
      EXPECT_EQ(run[i].steps, first[i].steps);
      EXPECT_EQ(run[i].failed_push, first[i].failed_push);
    }
}

}  // namespace
}  // namespace taskmap
