// Robot model loading: the shipped Panda (joints, limits, capsules), hand mounting, primitives
// and error messages.
#include "taskmap/reaching/robot_model.hpp"
#include "cpu_time.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "hostile_urdf.hpp"
#include "reaching_fixtures.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/xml_scan.hpp"

namespace taskmap {
namespace {

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(RobotModel, PandaHasSevenJointsWithFrankaLimitsAndCapsules) {
  const RobotModel& robot = test::pandaWithHand();
  ASSERT_EQ(robot.dofs(), 7);
  EXPECT_EQ(robot.dofNames()[0], "fer_joint1");
  EXPECT_DOUBLE_EQ(robot.lower()[3], -3.0718);
  EXPECT_DOUBLE_EQ(robot.upper()[5], 3.7525);
  EXPECT_DOUBLE_EQ(robot.velocityLimits()[6], 2.61);
  // Capsule model replaces the URDF's cylinder + sphere elements: one primitive per capsule.
  const RobotBody& link5 = robot.bodies()[robot.requireBody("fer_link5")];
  ASSERT_EQ(link5.shapes.size(), 2u);
  EXPECT_EQ(link5.shapes[0].type, PrimitiveType::kCapsule);
  EXPECT_NEAR(link5.shapes[0].half_u, 0.05, 1e-12);
  EXPECT_NEAR(link5.shapes[0].radius, 0.06, 1e-12);
  EXPECT_TRUE(robot.warnings().empty());
  EXPECT_EQ(robot.bodies()[robot.requireBody("fer_link7")].chain_depth, 7);
}

// The mount comes from the hand's sidecar (issue 30: reach used the humanoid's adapter for every
// hand). The humanoid's sidecar mount is the adapter pandaWithHumanoidHand uses; the bundled
// panda sits on the flange as Franka's hand does (palm 5.84 cm out, turned -45 degrees); a hand
// whose sidecar has no mount (the real Franka hand's, written from the README) is asked for one.
TEST(RobotModel, MountComesFromTheSidecarOrIsAskedFor) {
  const std::string hands = TASKMAP_HANDS_DIR;
  const HandModel humanoid = HandModel::load(hands + "/humanoid/humanoid.urdf");
  const HandMount m = mountFromSidecar(humanoid, "fer_link8");
  EXPECT_EQ(m.flange, "fer_link8");
  EXPECT_TRUE(m.palm_in_flange.isApprox(RobotModel::humanoidMountOnPanda().palm_in_flange, 1e-12));
  const HandMount panda = mountFromSidecar(HandModel::load(hands + "/panda/panda.urdf"), "link7");
  EXPECT_EQ(panda.flange, "link7");
  EXPECT_TRUE(panda.palm_in_flange.translation().isApprox(Eigen::Vector3d(0, 0, 0.0584), 1e-12));
  EXPECT_NEAR(Eigen::AngleAxisd(panda.palm_in_flange.linear()).angle(), M_PI / 4, 1e-12);
  const std::string franka =
      std::string(TEST_DATA_DIR) + "/real/hands/franka_hand/franka_hand.urdf";
  if (!std::filesystem::exists(franka)) GTEST_SKIP() << franka << " not present";
  const HandModel hand = HandModel::load(franka);
  ASSERT_FALSE(hand.mount());
  const std::string e = errorOf([&] { mountFromSidecar(hand, "fer_link8"); });
  EXPECT_NE(e.find("does not say how it is mounted"), std::string::npos) << e;
  EXPECT_NE(e.find("\"mount\": {\"xyz\""), std::string::npos) << e;
  EXPECT_NE(e.find("franka_hand.hand.json"), std::string::npos) << e;
  EXPECT_NE(e.find("--mount"), std::string::npos) << e;
}

TEST(RobotModel, HumanoidHandPerLinkBoxesBecomeSweptRectangles) {
  RobotModel robot = RobotModel::load(test::robotsDir() + "/panda/panda.urdf");
  HandMount mount = RobotModel::humanoidMountOnPanda();
  mount.hand_shapes = HandShapes::kPerLink;
  robot.mountHand(HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf"),
                  mount);
  ASSERT_GE(robot.palmBody(), 0);
  EXPECT_TRUE(robot.bodies()[robot.palmBody()].shapes.empty());
  const RobotBody& palm = robot.bodies()[robot.requireBody("hand/palm")];
  EXPECT_EQ(palm.role, BodyRole::kHand);
  EXPECT_EQ(palm.parent, robot.requireBody("fer_link8"));
  ASSERT_EQ(palm.shapes.size(), 1u);
  // Palm box 0.085 x 0.10 x 0.03: rectangle (0.085 - 0.03) x (0.10 - 0.03), radius 0.015.
  const Primitive& p = palm.shapes[0];
  EXPECT_EQ(p.type, PrimitiveType::kSweptRectangle);
  EXPECT_NEAR(p.radius, 0.015, 1e-12);
  EXPECT_NEAR(p.half_u, 0.0275, 1e-12);
  EXPECT_NEAR(p.half_v, 0.035, 1e-12);
  EXPECT_NEAR(std::abs(p.axes.col(2).z()), 1.0, 1e-12);  // normal along the palm z
}

TEST(RobotModel, HumanoidHandEnvelopeEnclosesEveryLinkPrimitive) {
  const RobotModel& robot = test::pandaWithHand();
  const RobotBody& palm = robot.bodies()[robot.palmBody()];
  ASSERT_EQ(palm.shapes.size(), 1u);
  const Primitive& env = palm.shapes[0];
  EXPECT_EQ(env.type, PrimitiveType::kSweptRectangle);
  // Open humanoid hand: palm 0.085 wide, fingers reach 0.05 + 0.048 + 0.028 + 0.024 beyond the
  // palm centre; the envelope is a flat plate about 3 cm thick.
  EXPECT_NEAR(env.radius, 0.015, 0.005);
  EXPECT_GT(2 * (env.half_u + env.radius), 0.09);
  EXPECT_GT(2 * (env.half_v + env.radius), 0.19);
  for (const RobotBody& b : robot.bodies()) {
    if (b.role == BodyRole::kHand && b.name != "palm") {
      EXPECT_TRUE(b.shapes.empty()) << b.name;
    }
  }
}

/// Mounts a hand URDF on the Panda flange with a 5 cm adapter along the flange z axis and checks
/// that the palm body sits there and carries an enveloping primitive.
void expectMountable(const std::string& urdf) {
  RobotModel robot = RobotModel::load(test::robotsDir() + "/panda/panda.urdf");
  const HandModel hand = HandModel::load(urdf);
  HandMount mount;
  mount.flange = "fer_link8";
  mount.palm_in_flange.translation() = Eigen::Vector3d(0, 0, 0.05);
  robot.mountHand(hand, mount);
  ASSERT_GE(robot.palmBody(), 0);
  const RobotBody& palm = robot.bodies()[robot.palmBody()];
  EXPECT_EQ(palm.parent, robot.requireBody("fer_link8"));
  EXPECT_TRUE(palm.origin.isApprox(mount.palm_in_flange));
  ASSERT_EQ(palm.shapes.size(), 1u);
  EXPECT_GT(palm.shapes[0].boundingRadius(), 0.02);
  EXPECT_EQ(robot.dofs(), 7);  // hand joints are fixed at the preshape
  int hand_bodies = 0;
  for (const RobotBody& b : robot.bodies()) hand_bodies += b.role == BodyRole::kHand;
  EXPECT_EQ(hand_bodies, static_cast<int>(hand.links().size()) + 1);
}

TEST(RobotModel, AnyHandMountsOnTheFlange) {
  expectMountable(std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf");
  expectMountable(std::string(TASKMAP_HANDS_DIR) + "/panda/panda.urdf");
}

TEST(RobotModel, RealHandsMountOnTheFlange) {
  // Real hands from public repositories (mesh collision geometry, mimic joints); skipped when
  // the shared inputs are absent.
  const std::string real = std::string(TASKMAP_SOURCE_DIR) + "/../shared/real/hands";
  if (!std::filesystem::exists(real)) GTEST_SKIP() << "no " << real;
  expectMountable(real + "/franka_hand/franka_hand.urdf");
  expectMountable(real + "/allegro_right/allegro_hand_description_right.urdf");
}

TEST(RobotModel, UrdfShapesBecomePrimitives) {
  const RobotModel robot =
      RobotModel::load(test::writeTempFile("mixed_shapes.urdf", test::mixedJointsUrdf()));
  const RobotBody& b = robot.bodies()[robot.requireBody("b")];
  ASSERT_EQ(b.shapes.size(), 1u);
  EXPECT_EQ(b.shapes[0].type, PrimitiveType::kCapsule);
  EXPECT_NEAR(b.shapes[0].half_u, 0.1, 1e-12);  // cylinder -> enclosing capsule
  EXPECT_NEAR(b.shapes[0].radius, 0.03, 1e-12);
  const RobotBody& c = robot.bodies()[robot.requireBody("c")];
  EXPECT_NEAR(c.shapes[0].half_u, 0.0, 1e-12);  // sphere
  EXPECT_DOUBLE_EQ(robot.lower()[2], -M_PI);    // continuous joint
  EXPECT_EQ(robot.bodies()[robot.requireBody("b")].joint, JointType::kPrismatic);
}

TEST(RobotModel, ErrorsNameTheFileAndTheProblem) {
  EXPECT_NE(
      errorOf([] { RobotModel::load("/nonexistent/robot.urdf"); }).find("/nonexistent/robot.urdf"),
      std::string::npos);
  const std::string bad = test::writeTempFile("bad.urdf", "<robot name='x'><link name='a'>");
  EXPECT_NE(errorOf([&] { RobotModel::load(bad); }).find("cannot parse robot URDF"),
            std::string::npos);
  const std::string floating = test::writeTempFile(
      "floating.urdf",
      "<robot name='f'><link name='a'/><link name='b'/><joint name='j' type='floating'>"
      "<parent link='a'/><child link='b'/></joint></robot>");
  EXPECT_NE(errorOf([&] { RobotModel::load(floating); }).find("floating or planar"),
            std::string::npos);
  const std::string nolimit = test::writeTempFile(
      "nolimit.urdf",
      "<robot name='f'><link name='a'/><link name='b'/><joint name='j' type='prismatic'>"
      "<parent link='a'/><child link='b'/><axis xyz='1 0 0'/></joint></robot>");
  EXPECT_NE(errorOf([&] { RobotModel::load(nolimit); }).find("limits"), std::string::npos);
  RobotModel robot = test::pandaWithHand();
  EXPECT_NE(errorOf([&] { robot.requireBody("elbow"); }).find("fer_link3"), std::string::npos);
  EXPECT_NE(errorOf([&] {
              robot.addEnvironmentBody("fer_link1", Eigen::Isometry3d::Identity(), {});
            }).find("exists already"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              robot.mountHand(
                  HandModel::load(std::string(TASKMAP_HANDS_DIR) + "/humanoid/humanoid.urdf"),
                  RobotModel::humanoidMountOnPanda());
            }).find("carries a hand already"),
            std::string::npos);
  EXPECT_THROW(Primitive::capsule(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), -1.0), Error);
}

TEST(RobotModel, BadCapsuleModelIsRejectedWithTheFileName) {
  const std::string urdf = test::writeTempFile("caps.urdf", test::mixedJointsUrdf());
  const std::string caps = test::writeTempFile("caps.capsules.json", R"({"links": {"zz": []}})");
  const std::string msg = errorOf([&] { RobotModel::load(urdf); });
  EXPECT_NE(msg.find("caps.capsules.json"), std::string::npos) << msg;
  EXPECT_NE(msg.find("no such link"), std::string::npos) << msg;
  test::writeTempFile("caps.capsules.json",
                      R"({"links": {"a": [{"p0": [0, 0], "p1": [0, 0, 1], "radius": 0.1}]}})");
  EXPECT_NE(errorOf([&] { RobotModel::load(urdf); }).find("expected [x, y, z]"), std::string::npos);
}

// Robot URDFs of hostile size or shape (issue 32): the walk is iterative and linear, the size and
// the XML depth are checked before TinyXML, detached cycles and FIFOs are refused.
TEST(RobotModel, HostileUrdfsAreLoadedFastOrRefused) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("taskmap_robot_urdf_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const auto timed = [](const std::string& path, double* seconds) {
    const double t0 = testing::cpuSeconds();
    const std::string e = errorOf([&] { RobotModel::load(path); });
    *seconds = testing::cpuSeconds() - t0;
    return e;
  };
  double s = 0;
  const std::string chain = (dir / "chain.urdf").string();
  testing::writeText(chain, testing::chainUrdf(kMaxUrdfLinks - 1));
  EXPECT_EQ(timed(chain, &s), "no error");
  EXPECT_LT(s, 1.0);
  EXPECT_EQ(RobotModel::load(chain).dofs(), static_cast<int>(kMaxUrdfLinks - 1));
  const std::string huge = (dir / "huge.urdf").string();
  testing::writeText(huge, testing::chainUrdf(100000));
  std::string e = timed(huge, &s);
  EXPECT_NE(e.find("limit of 4096"), std::string::npos) << e;
  EXPECT_NE(e.find(huge), std::string::npos) << e;
  EXPECT_LT(s, 1.0);
  const std::string deep = (dir / "deep.urdf").string();
  testing::writeText(deep, testing::deepUrdf(100000));
  e = timed(deep, &s);
  EXPECT_NE(e.find("nested more than 64"), std::string::npos) << e;
  const std::string cycle = (dir / "cycle.urdf").string();
  testing::writeText(cycle, testing::detachedCycleUrdf());
  e = timed(cycle, &s);
  EXPECT_NE(e.find(cycle), std::string::npos) << e;
  EXPECT_NE(e.find("c1"), std::string::npos) << e;
  const std::string fifo = (dir / "pipe.urdf").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  e = timed(fifo, &s);
  EXPECT_NE(e.find("FIFO"), std::string::npos) << e;
  fs::remove_all(dir);
}

// Hands (hands) and robots (reaching) read URDFs with one reader under one lock around
// console_bridge's process-global output handler: loaded at once from many threads (two Python
// threads, say), every good file loads and every broken one quotes exactly its own message.
TEST(RobotModel, HandsAndRobotsLoadConcurrentlyWithTheirOwnMessages) {
  // 200 fixed links, then a revolute joint without <limit>: urdfdom names that joint, after
  // parsing long enough for the loads of other threads to overlap.
  const auto broken = [](const std::string& joint) {
    std::string xml = "<robot name=\"r\"><link name=\"l0\"/>";
    for (int i = 1; i <= 200; ++i)
      xml += "<link name=\"l" + std::to_string(i) + "\"/><joint name=\"f" + std::to_string(i) +
             "\" type=\"fixed\"><parent link=\"l" + std::to_string(i - 1) + "\"/><child link=\"l" +
             std::to_string(i) + "\"/></joint>";
    return xml + "<link name=\"b\"/><joint name=\"" + joint +
           "\" type=\"revolute\"><parent link=\"l200\"/><child link=\"b\"/>"
           "<axis xyz=\"0 0 1\"/></joint></robot>";
  };
  const std::string hand_urdf = std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf";
  const std::string robot_urdf = test::robotsDir() + "/panda/panda.urdf";
  const std::size_t hand_links = HandModel::load(hand_urdf).links().size();
  const std::size_t robot_bodies = RobotModel::load(robot_urdf).bodies().size();
  constexpr int kThreads = 8;
  constexpr int kRounds = 40;
  std::vector<std::string> files(kThreads), expected(kThreads), failures(kThreads);
  for (int t = 0; t < kThreads; ++t) {
    files[t] = test::writeTempFile("race" + std::to_string(t) + ".urdf",
                                   broken("race_joint" + std::to_string(t)));
    // Even threads load hands, odd ones robots: the message a load alone gives.
    expected[t] = errorOf([&] {
      if (t % 2 == 0)
        HandModel::loadKinematics(files[t]);
      else
        RobotModel::load(files[t]);
    });
    ASSERT_NE(expected[t].find("race_joint" + std::to_string(t)), std::string::npos);
  }
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int r = 0; r < kRounds && failures[t].empty(); ++r) {
        std::string got;
        if (r % 8 == 0) {
          const bool ok = t % 2 == 0 ? HandModel::load(hand_urdf).links().size() == hand_links
                                     : RobotModel::load(robot_urdf).bodies().size() == robot_bodies;
          if (!ok) failures[t] = "a good file loaded differently";
          continue;
        }
        got = errorOf([&] {
          if (t % 2 == 0)
            HandModel::loadKinematics(files[t]);
          else
            RobotModel::load(files[t]);
        });
        if (got != expected[t]) failures[t] = got;
      }
    });
  }
  for (auto& th : threads) th.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(failures[t], "") << "thread " << t;
}

}  // namespace
}  // namespace taskmap
