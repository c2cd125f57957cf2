// Coupled closing (grasp_sim/src/trial_coupling.cpp) and fingertip grasps (Trial::placePalm):
// closed-form outcomes on boxes for the test hands of tests/data/hands.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "error_matchers.hpp"
#include "grasp_fixtures.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/random.hpp"
#include "taskmap/grasp_sim/grasp_simulator.hpp"
#include "test_meshes.hpp"

namespace taskmap {
namespace {

using testing::fromAbove;
constexpr double kTol = testing::kContactTolerance;
constexpr double kInf = std::numeric_limits<double>::infinity();

HandModel pandaMimic() {
  return HandModel::load(testing::testHandPath("panda_mimic"));
}
HandModel pandaIndependent() {
  return testing::referenceHand("panda");
}
HandModel pandaSidecarCoupled() {
  return HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/panda/panda.urdf",
                         std::string(TEST_DATA_DIR) + "/hands/panda_coupled.hand.json");
}

int fingers(const GraspResult& r) {
  return static_cast<int>(r.fingers_in_contact.size());
}

TriangleMesh twoBoxes(const TriangleMesh& a, const TriangleMesh& b) {
  TriangleMesh m = a;
  const int n = static_cast<int>(a.vertices.size());
  m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const auto& f : b.faces) m.faces.emplace_back(f[0] + n, f[1] + n, f[2] + n);
  return m;
}

// A 4 cm box with the hand 8 mm off centre: the right jaw touches first (at q = 0.028), the
// hand shifts 8 mm back over the centre while the left jaw closes at twice the speed, both jaws
// touch at q = 0.02 and the squeeze presses both by 1 mm.
TEST(CoupledClosing, MimicJawsCentreTheHandOnAnOffsetBox) {
  const double w = 0.04, off = 0.008;
  for (const HandModel& hand : {pandaMimic(), pandaSidecarCoupled()}) {
    SCOPED_TRACE(hand.sidecarPath());
    GraspSimulator sim(testing::makeBox(w, 0.03, 0.10), hand);
    const GraspResult r = sim.simulate(fromAbove(Eigen::Vector3d(off, 0.0, -0.01)));
    ASSERT_EQ(r.status, GraspStatus::kOk) << r.message;
    EXPECT_EQ(fingers(r), 2);
    EXPECT_TRUE(r.palm_contact);
    EXPECT_NEAR(r.stats.centring_shift, off, kTol);
    EXPECT_NEAR(r.pose.position.x(), 0.0, kTol);   // centred over the box
    EXPECT_NEAR(r.pose.position.y(), 0.0, 1e-12);  // not moved across the closing direction
    EXPECT_NEAR(r.pose.position.z(), 0.05, kTol);  // palm touching (reported, squeeze undone)
    EXPECT_NEAR(r.joints[0], 0.5 * w - hand.squeeze(), kTol);
    for (const Contact& c : r.contacts) {
      EXPECT_GT(c.depth, 0.0);
      EXPECT_LT(c.depth, 2 * hand.squeeze() + kTol);
    }
  }
  // Without centring the mimic pair stops at the first touch: one jaw.
  GraspSimOptions o;
  o.centre_coupled = false;
  GraspSimulator stiff(testing::makeBox(w, 0.03, 0.10), pandaMimic(), o);
  const GraspResult s = stiff.simulate(fromAbove(Eigen::Vector3d(off, 0.0, -0.01)));
  ASSERT_EQ(s.status, GraspStatus::kOk) << s.message;
  EXPECT_EQ(s.fingers_in_contact, std::vector<std::string>{"right"});
  EXPECT_EQ(s.stats.centring_shift, 0.0);
  EXPECT_NEAR(s.pose.position.x(), off, 1e-12);
}

// Independent jaws (the bundled panda) are no mechanism: each stops on its own contact, the
// hand does not move, as before coupling existed.
TEST(CoupledClosing, IndependentJawsDoNotShiftTheHand) {
  const HandModel hand = pandaIndependent();
  GraspSimulator sim(testing::makeBox(0.04, 0.03, 0.10), hand);
  const GraspResult r = sim.simulate(fromAbove(Eigen::Vector3d(0.008, 0.0, -0.01)));
  ASSERT_EQ(r.status, GraspStatus::kOk) << r.message;
  EXPECT_EQ(fingers(r), 2);
  EXPECT_EQ(r.stats.centring_shift, 0.0);
  EXPECT_NEAR(r.pose.position.x(), 0.008, 1e-12);
  EXPECT_NEAR(r.joints[0], 0.02 - 0.008 - hand.squeeze(), kTol);
  EXPECT_NEAR(r.joints[1], 0.02 + 0.008 - hand.squeeze(), kTol);
}

// A wall 1.5 mm beside the palm (on the side the hand shifts toward) jams the shift: the palm
// stops when it touches the wall, the other jaw never arrives.
TEST(CoupledClosing, PalmAgainstAWallJamsTheShift) {
  const HandModel hand = pandaMimic();
  const double off = 0.008, gap = 0.0015;
  // Palm body 0.20 m along the closing direction: its edge is at x = off - 0.10.
  const double wall_x = off - 0.10 - gap - 0.005;
  const TriangleMesh mesh = twoBoxes(testing::makeBox(0.04, 0.03, 0.10),
                                     testing::makeBox(0.01, 0.10, 0.30, {wall_x, 0.0, 0.05}));
  GraspSimulator sim(mesh, hand);
  const GraspResult r = sim.simulate(fromAbove(Eigen::Vector3d(off, 0.0, -0.01)));
  ASSERT_EQ(r.status, GraspStatus::kOk) << r.message;
  EXPECT_EQ(r.fingers_in_contact, std::vector<std::string>{"right"});
  EXPECT_GT(r.stats.centring_shift, gap - kTol - 1e-6);
  EXPECT_LE(r.stats.centring_shift, gap + 1e-6);
  for (const Contact& c : r.contacts) EXPECT_GT(c.point.x(), wall_x + 0.005);  // none on the wall
}

// Coupled closing keeps the simulator deterministic and thread-independent.
TEST(CoupledClosing, ThreadsMatchSequentialRun) {
  const HandModel hand = pandaMimic();
  GraspSimulator sim(testing::makeCylinder(0.03, 0.16, 40, 1), hand);
  std::vector<Pose> poses;
  for (int i = 0; i < 40; ++i) {
    Rng rng(7, static_cast<std::uint64_t>(i));
    Pose p;
    p.position = Eigen::Vector3d(rng.uniform(-0.02, 0.02), rng.uniform(-0.06, 0.06),
                                 rng.uniform(-0.02, 0.02));
    p.orientation = rng.rotation();
    poses.push_back(p);
  }
  std::vector<GraspResult> seq, par(poses.size());
  for (const Pose& p : poses) seq.push_back(sim.simulate(p));
  std::thread t([&] {
    for (std::size_t i = 1; i < poses.size(); i += 2) par[i] = sim.simulate(poses[i]);
  });
  for (std::size_t i = 0; i < poses.size(); i += 2) par[i] = sim.simulate(poses[i]);
  t.join();
  int shifted = 0, two = 0, ok = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_EQ(seq[i].status, par[i].status);
    EXPECT_EQ(seq[i].pose.position, par[i].pose.position);
    EXPECT_EQ(seq[i].joints, par[i].joints);
    EXPECT_EQ(seq[i].contacts.size(), par[i].contacts.size());
    shifted += seq[i].stats.centring_shift > 0.0;
    if (seq[i].status == GraspStatus::kOk) {
      ++ok;
      two += fingers(seq[i]) == 2;
    }
  }
  EXPECT_GT(shifted, 0);  // the set exercises the shift
  EXPECT_EQ(two, ok);     // every completed grasp of the cylinder has both jaws
}

// Fingertip grasps (Robotiq 2F-85 style test hand, standoff 0.02 m in its sidecar): the palm
// stops 2 cm above the top of a 3 cm box and the pads pinch it; the same pose as a palm grasp
// presses the palm on the box.
TEST(FingertipGrasp, StandoffPinchWithoutThePalm) {
  const HandModel hand = HandModel::load(testing::testHandPath("robotiq_2f85_style"));
  ASSERT_EQ(hand.graspMode(), GraspMode::kFingertip);
  const double top = 0.05;
  GraspSimulator sim(testing::makeBox(0.03, 0.03, 0.10), hand);
  const GraspResult r = sim.simulate(fromAbove(Eigen::Vector3d(0.004, 0.0, 0.0)));
  ASSERT_EQ(r.status, GraspStatus::kOk) << r.message;
  EXPECT_FALSE(r.palm_contact);
  EXPECT_EQ(fingers(r), 2);
  EXPECT_NEAR(r.pose.position.z(), top + 0.02, kTol);  // the standoff
  EXPECT_GT(r.stats.standoff, 0.0);
  EXPECT_NEAR(r.pose.position.x(), 0.0, kTol);  // coupled jaws centred the hand
  for (const Contact& c : r.contacts) EXPECT_LT(c.point.z(), top - 0.02 + 0.065 - 0.02 + 1e-9);

  GraspSimOptions palm;
  palm.grasp_mode = GraspMode::kPalm;
  GraspSimulator power(testing::makeBox(0.03, 0.03, 0.10), hand, palm);
  const GraspResult p = power.simulate(fromAbove(Eigen::Vector3d(0.004, 0.0, 0.0)));
  ASSERT_EQ(p.status, GraspStatus::kOk) << p.message;
  EXPECT_TRUE(p.palm_contact);
  EXPECT_NEAR(p.pose.position.z(), top, kTol);  // the palm touching (reported, squeeze undone)

  // Standoff from the options; 0 = stop at the first contact (here the palm touches first).
  GraspSimOptions zero;
  zero.standoff = 0.0;
  GraspSimulator first(testing::makeBox(0.03, 0.03, 0.10), hand, zero);
  const GraspResult z = first.simulate(fromAbove(Eigen::Vector3d(0.004, 0.0, 0.0)));
  EXPECT_NEAR(z.pose.position.z(), top, kTol);  // touching, not pressed
  EXPECT_EQ(z.stats.standoff, 0.0);
}

// A finger that touches first stops the approach before the standoff: on a box wider than the
// open jaws the fingertips land on the top face, 6.5 cm below the palm.
TEST(FingertipGrasp, FirstFingerContactStopsTheApproach) {
  const HandModel hand = HandModel::load(testing::testHandPath("robotiq_2f85_style"));
  GraspSimulator sim(testing::makeBox(0.12, 0.03, 0.10), hand);
  const GraspResult r = sim.simulate(fromAbove(Eigen::Vector3d(0.0, 0.0, 0.0)));
  EXPECT_NEAR(r.pose.position.z(), 0.05 + 0.065, kTol);
  EXPECT_EQ(r.stats.standoff, 0.0);
  EXPECT_NE(r.status, GraspStatus::kNoPalmContact);  // no palm needed
}

// The standoff in force: the option, else the sidecar's, else a tenth of the palm-to-fingertip
// length (at least 4 contact tolerances).
TEST(FingertipGrasp, StandoffResolvesOptionThenSidecarThenHand) {
  const HandModel robotiq = HandModel::load(testing::testHandPath("robotiq_2f85_style"));
  const HandModel panda = testing::referenceHand("panda");
  ASSERT_TRUE(robotiq.hasStandoff());
  ASSERT_FALSE(panda.hasStandoff());
  GraspSimOptions o;
  EXPECT_DOUBLE_EQ(resolveStandoff(robotiq, o), 0.02);
  EXPECT_DOUBLE_EQ(resolveStandoff(panda, o), 0.1 * panda.rotationScale());
  EXPECT_GT(resolveStandoff(panda, o), 4.0 * o.contact_tolerance);
  o.standoff = 0.0;
  EXPECT_EQ(resolveStandoff(robotiq, o), 0.0);
  EXPECT_EQ(resolveStandoff(panda, o), 0.0);
  o.standoff = 0.6;
  EXPECT_TRUE(testing::throwsError([&] { resolveStandoff(panda, o); }, {"standoff", "0.5"}));
}

// Default fingertip grasps keep the palm off the object (issue 30: with standoff 0 the
// approach stopped on the palm). The real Franka hand (tests/data/real) and the Robotiq-style
// test hand with its sidecar's standoff removed, fingertip mode from the options, on the
// soup-can-sized cylinder: completed trials end with the palm more than twice the contact
// tolerance from the can, except where coupled jaws shift the palm sideways onto the can's
// curve (measured: 1 of 62 for the Robotiq-style hand, 0 of 58 for the Franka hand; at most
// 5 % allowed); with standoff 0, 12 of 62 and 10 of 58 end with the palm touching.
TEST(FingertipGrasp, DefaultStandoffKeepsThePalmOff) {
  const std::string franka_urdf =
      std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/franka_hand.urdf";
  if (!std::filesystem::exists(franka_urdf)) GTEST_SKIP() << franka_urdf << " not present";
  const std::string sidecar = ::testing::TempDir() + "/robotiq_no_standoff.hand.json";
  {
    std::ifstream in(std::string(TEST_DATA_DIR) +
                     "/hands/robotiq_2f85_style/robotiq_2f85_style.hand.json");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string key = ", \"standoff\": 0.02";
    const auto at = text.find(key);
    ASSERT_NE(at, std::string::npos);
    text.erase(at, key.size());
    std::ofstream(sidecar) << text;
  }
  const ObjectModel can = ObjectModel::load(std::string(TEST_DATA_DIR) + "/meshes/soup_can.obj");
  const std::vector<HandModel> hands = {
      HandModel::load(testing::testHandPath("robotiq_2f85_style"), sidecar),
      HandModel::load(franka_urdf)};
  for (const HandModel& hand : hands) {
    ASSERT_FALSE(hand.hasStandoff()) << hand.name();
    GraspSimOptions fingertip, zero;
    fingertip.grasp_mode = zero.grasp_mode = GraspMode::kFingertip;
    zero.standoff = 0.0;
    GraspSimulator sim(can, hand, fingertip), touching(can, hand, zero);
    int ok = 0, touch = 0, zero_ok = 0, zero_touch = 0;
    double least = kInf;
    for (int i = 0; i < 80; ++i) {
      Rng rng(11, static_cast<std::uint64_t>(i));
      Pose p;
      p.position = can.sampleInside(rng);
      p.orientation = rng.rotation();
      const GraspResult r = sim.simulate(p), z = touching.simulate(p);
      if (r.status == GraspStatus::kOk) {
        ++ok;
        EXPECT_FALSE(r.palm_contact) << hand.name() << " trial " << i;
        if (!(r.stats.palm_gap > 2.0 * kTol)) {
          ++touch;
          std::cout << hand.name() << " trial " << i << ": palm gap " << r.stats.palm_gap
                    << " m, backed off " << r.stats.standoff << " m, centring shift "
                    << r.stats.centring_shift << " m\n";
        }
        least = std::min(least, r.stats.palm_gap);
      }
      if (z.status == GraspStatus::kOk) {
        ++zero_ok;
        zero_touch += z.stats.palm_gap <= kTol;
      }
    }
    std::cout << hand.name() << ": default standoff " << resolveStandoff(hand, GraspSimOptions{})
              << " m, " << ok << " completed trials of 80, " << touch
              << " with the palm within 1 mm, least palm gap " << least
              << " m; standoff 0: " << zero_touch << " of " << zero_ok
              << " completed trials with the palm touching\n";
    EXPECT_GE(ok, 8) << hand.name();
    EXPECT_LE(20 * touch, ok) << hand.name() << ": " << touch << " of " << ok;
    EXPECT_GT(zero_touch, 3 * touch) << hand.name();
    EXPECT_GT(zero_touch, 0) << hand.name() << ": standoff 0 never touched (the test cannot fail)";
  }
}

TEST(FingertipGrasp, StandoffOptionIsValidated) {
  GraspSimOptions o;
  o.standoff = 0.6;
  EXPECT_TRUE(testing::throwsError([&] { o.validate(); }, {"standoff", "0.5"}));
}

}  // namespace
}  // namespace taskmap

namespace taskmap {
namespace {

// Real inputs (tests/data/real, see its README): the Franka hand, whose right jaw <mimic>s the
// left, on the YCB banana. Trials from random poses inside the banana: with centring nearly
// every completed trial holds the banana with both jaws; without it most hold it with one.
TEST(CoupledClosing, RealFrankaHandOnTheYcbBanana) {
  const std::string real = std::string(TEST_DATA_DIR) + "/real";
  const std::string urdf = real + "/hands/franka_hand/franka_hand.urdf";
  const std::string mesh = real + "/objects/ycb_011_banana.obj";
  if (!std::filesystem::exists(urdf) || !std::filesystem::exists(mesh))
    GTEST_SKIP() << "real inputs not in " << real;
  const HandModel hand = HandModel::load(urdf);
  const ObjectModel banana = ObjectModel::load(mesh);
  GraspSimOptions stiff_options;
  stiff_options.centre_coupled = false;
  GraspSimulator sim(banana, hand), stiff(banana, hand, stiff_options);
  int ok = 0, two = 0, stiff_ok = 0, stiff_two = 0;
  for (int i = 0; i < 40; ++i) {
    Rng rng(3, static_cast<std::uint64_t>(i));
    Pose p;
    p.position = banana.sampleInside(rng);
    p.orientation = rng.rotation();
    const GraspResult r = sim.simulate(p), s = stiff.simulate(p);
    if (r.status == GraspStatus::kOk) {
      ++ok;
      two += fingers(r) == 2;
    }
    if (s.status == GraspStatus::kOk) {
      ++stiff_ok;
      stiff_two += fingers(s) == 2;
    }
  }
  std::cout << "centred: " << two << " of " << ok
            << " completed trials with both jaws; stiff: " << stiff_two << " of " << stiff_ok
            << "\n";
  ASSERT_GE(ok, 10);
  EXPECT_GE(10 * two, 9 * ok) << two << " of " << ok << " completed trials with both jaws";
  EXPECT_LT(2 * stiff_two, stiff_ok) << stiff_two << " of " << stiff_ok << " without centring";
}

// Fingertip grasps on a real scan: the Robotiq-2F-85-style test hand pinches the YCB banana
// (tests/data/real) with both pads and never with the palm.
TEST(FingertipGrasp, PinchesTheYcbBanana) {
  const std::string mesh = std::string(TEST_DATA_DIR) + "/real/objects/ycb_011_banana.obj";
  if (!std::filesystem::exists(mesh)) GTEST_SKIP() << mesh << " not present";
  const ObjectModel banana = ObjectModel::load(mesh);
  GraspSimulator sim(banana, HandModel::load(testing::testHandPath("robotiq_2f85_style")));
  int pinch = 0;
  for (int i = 0; i < 60; ++i) {
    Rng rng(5, static_cast<std::uint64_t>(i));
    Pose p;
    p.position = banana.sampleInside(rng);
    p.orientation = rng.rotation();
    const GraspResult r = sim.simulate(p);
    EXPECT_FALSE(r.palm_contact) << "trial " << i;
    pinch += r.status == GraspStatus::kOk && fingers(r) == 2;
  }
  EXPECT_GE(pinch, 6) << pinch << " two-pad grasps in 60 trials";
}

}  // namespace
}  // namespace taskmap
