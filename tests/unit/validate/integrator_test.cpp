// The hold test's integrator (docs/VALIDATION.md, "Parameters"): DexGraspBench integrates
// `implicitfast`, which MuJoCo 2.2.2 lacks. Its Euler integrator is implicit in joint damping,
// which is all implicitfast takes implicitly for a scene whose servos have no velocity gain:
// MuJoCo itself is the oracle (one step of a damped hinge against the implicit update
// v1 = v0 I / (I + h b)). The scene names `implicit` by default, Euler for implicitfast, and
// `implicit` for implicitfast when a stated servo has a velocity gain.
#include <gtest/gtest.h>

#include <mujoco/mujoco.h>

#include <string>

#include "build_fixtures.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/validate/hold_test.hpp"

namespace taskmap {
namespace {

/// Velocity of a damped hinge (armature `inertia` kg m^2, damping `damping` N m s/rad, no other
/// force) after one step of `h` seconds from 1 rad/s with MuJoCo's `integrator`.
double oneStep(const std::string& integrator, double inertia, double damping, double h) {
  const std::string xml =
      "<mujoco><option timestep=\"" + std::to_string(h) + "\" gravity=\"0 0 0\" integrator=\"" +
      integrator + "\"/><worldbody><body><joint type=\"hinge\" axis=\"0 0 1\" damping=\"" +
      std::to_string(damping) + "\" armature=\"" + std::to_string(inertia) +
      "\"/><geom type=\"sphere\" size=\"0.01\" mass=\"1e-9\" contype=\"0\" conaffinity=\"0\"/>"
      "</body></worldbody></mujoco>";
  char error[1000] = "";
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  mj_makeEmptyFileVFS(&vfs, "hinge.xml", static_cast<int>(xml.size()));
  const int f = mj_findFileVFS(&vfs, "hinge.xml");
  std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs.filedata[f]));
  mjModel* m = mj_loadXML("hinge.xml", &vfs, error, sizeof error);
  mj_deleteVFS(&vfs);
  EXPECT_NE(m, nullptr) << error;
  if (!m) return 0.0;
  mjData* d = mj_makeData(m);
  d->qvel[0] = 1.0;
  mj_step(m, d);
  const double v = d->qvel[0];
  mj_deleteData(d);
  mj_deleteModel(m);
  return v;
}

TEST(Integrator, MujocosEulerIsImplicitInJointDamping) {
  // h b / I = 10: an explicit step would reverse the hinge (1 - 10 = -9).
  const double inertia = 1e-4, damping = 0.25, h = 0.004;
  const double implicit_update = inertia / (inertia + h * damping);
  EXPECT_NEAR(oneStep("Euler", inertia, damping, h), implicit_update, 1e-9);
  EXPECT_NEAR(oneStep("implicit", inertia, damping, h), implicit_update, 1e-9);
  EXPECT_GT(oneStep("Euler", inertia, damping, h), 0.0);
}

const HandModel& barrett() {
  static const HandModel h =
      HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  return h;
}

TEST(Integrator, TheSceneNamesImplicitByDefaultAndEulerForImplicitFast) {
  HoldTestOptions o;
  EXPECT_EQ(o.integrator, HoldTestOptions::Integrator::kImplicit);
  const std::string exact = HoldTester(barrett(), testing::boxObject(), o).mjcf();
  EXPECT_NE(exact.find("integrator=\"implicit\""), std::string::npos);
  o.integrator = HoldTestOptions::Integrator::kImplicitFast;
  const std::string fast = HoldTester(barrett(), testing::boxObject(), o).mjcf();
  EXPECT_NE(fast.find("integrator=\"Euler\""), std::string::npos);
}

TEST(Integrator, BothIntegratorsLetJawsHoldTheBox) {
  HoldTestOptions o;
  o.integrator = HoldTestOptions::Integrator::kImplicitFast;
  const HoldTester fast(testing::pandaHand(), testing::boxObject(), o);
  const HoldTester exact(testing::pandaHand(), testing::boxObject(), HoldTestOptions{});
  for (const double q : {0.02, 0.019}) {
    const Pose palm = testing::topBoxGrasp(0.061);
    const HoldResult a = fast.test(palm, Eigen::Vector2d(q, q));
    const HoldResult b = exact.test(palm, Eigen::Vector2d(q, q));
    EXPECT_TRUE(a.holds) << holdStatusName(a.status);
    EXPECT_TRUE(b.holds) << holdStatusName(b.status);
    EXPECT_NEAR(a.max_translation, b.max_translation, 1e-3);
  }
}

TEST(Integrator, AServoWithAVelocityGainIsIntegratedImplicit) {
  // The LEAP hand's MJCF states kv 0.01 on its servos: implicitfast would take that derivative,
  // Euler does not, so the scene integrates `implicit`; with the protocol's dynamics, Euler.
  const HandModel leap =
      HandModel::load(std::string(TEST_DATA_DIR) + "/real/hands/leap_hand_mjcf/right_hand.xml");
  HoldTestOptions o;
  o.integrator = HoldTestOptions::Integrator::kImplicitFast;
  EXPECT_NE(HoldTester(leap, testing::boxObject(), o).mjcf().find("integrator=\"implicit\""),
            std::string::npos);
  o.stated_dynamics = false;
  EXPECT_NE(HoldTester(leap, testing::boxObject(), o).mjcf().find("integrator=\"Euler\""),
            std::string::npos);
}

TEST(Integrator, NamesRoundTripAndAnUnknownOneIsRefused) {
  for (const auto i :
       {HoldTestOptions::Integrator::kImplicitFast, HoldTestOptions::Integrator::kImplicit})
    EXPECT_EQ(integratorFromName(integratorName(i)), i);
  try {
    integratorFromName("RK4");
    FAIL() << "RK4 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("implicitfast or implicit"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace taskmap
