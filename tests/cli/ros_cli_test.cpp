// A hand from a ROS description package (label cli): package:// mesh paths found through the
// package that holds the URDF, --package-path and ROS_PACKAGE_PATH; a .xacro file answered
// with what to do. The package layouts are built in a temporary folder from the real Franka
// hand (tests/data/real).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_run.hpp"
#include "scratch_dir.hpp"

namespace {

namespace fs = std::filesystem;

using taskmap::testing::CliRun;
using taskmap::testing::realInput;
using taskmap::testing::runTaskmap;

class RosCli : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = scratch_.root();
    // src/franka_description: package.xml, meshes/collision/hand.stl.
    const fs::path pkg = root_ / "src" / "franka_description";
    fs::create_directories(pkg / "meshes" / "collision");
    std::ofstream(pkg / "package.xml")
        << "<package format=\"3\"><name>franka_description</name></package>\n";
    fs::copy_file(realInput("hands/franka_hand/meshes/collision/hand.stl"),
                  pkg / "meshes" / "collision" / "hand.stl");
    std::ifstream in(realInput("hands/franka_hand/franka_hand.urdf"));
    urdf_text_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    const std::string from = "filename=\"meshes/collision/hand.stl\"";
    const auto at = urdf_text_.find(from);
    ASSERT_NE(at, std::string::npos);
    urdf_text_.replace(at, from.size(),
                       "filename=\"package://franka_description/meshes/collision/hand.stl\"");
  }

  /// The URDF with its package:// path and the real sidecar, written into `dir`.
  std::string writeHand(const fs::path& dir) const {
    fs::create_directories(dir);
    std::ofstream(dir / "franka_hand.urdf") << urdf_text_;
    fs::copy_file(realInput("hands/franka_hand/franka_hand.hand.json"),
                  dir / "franka_hand.hand.json", fs::copy_options::overwrite_existing);
    return (dir / "franka_hand.urdf").string();
  }
  static CliRun run(const std::string& args, const std::string& env = "env -u ROS_PACKAGE_PATH") {
    return taskmap::testing::runShell(env + " " + std::string(TASKMAP_BINARY_DIR) +
                                      "/bin/taskmap " + args);
  }

  taskmap::testing::ScratchDir scratch_{"ros_cli"};  // removed with the fixture
  fs::path root_;
  std::string urdf_text_;
};

TEST_F(RosCli, PackageHoldingTheUrdfIsFound) {
  const std::string urdf = writeHand(root_ / "src" / "franka_description" / "urdf");
  const CliRun r = run("hand-info " + urdf);
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("panda_hand           package://franka_description/meshes/collision/"
                       "hand.stl part 0"),
            std::string::npos)
      << r.out;
  // A sibling package of a hand package in the same workspace.
  const std::string sibling = writeHand(root_ / "src" / "my_hand" / "urdf");
  EXPECT_EQ(run("hand-info " + sibling).code, 0);
}

TEST_F(RosCli, PackagePathAndRosPackagePath) {
  const std::string urdf = writeHand(root_ / "elsewhere");
  CliRun r = run("hand-info " + urdf);
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_NE(r.out.find("collision mesh 'package://franka_description/meshes/collision/hand.stl': "
                       "ROS package 'franka_description' not found"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("pass --package-path DIR"), std::string::npos) << r.out;
  // --package-path: the package itself, or a folder holding it; on hand-info and build.
  r = run("hand-info " + urdf + " --package-path " +
          (root_ / "src" / "franka_description").string());
  EXPECT_EQ(r.code, 0) << r.out;
  r = run("hand-info --package-path " + (root_ / "nowhere").string() + " " + urdf);
  EXPECT_NE(r.code, 0) << r.out;
  r = run("hand-info --package-path " + root_.string() + " --package-path " +
          (root_ / "src").string() + " " + urdf);
  EXPECT_EQ(r.code, 0) << r.out;
  const std::string out = (root_ / "m.h5").string();
  r = run("build --object " + realInput("objects/ycb_011_banana.obj") + " --hand " + urdf + " -o " +
          out + " --package-path " + (root_ / "src").string() +
          " --valid 1 --trials 200 --threads 1 --hold-test off -q");
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_TRUE(fs::exists(out));
  // ROS_PACKAGE_PATH.
  r = run("hand-info " + urdf, "env ROS_PACKAGE_PATH=/nonexistent:" + (root_ / "src").string());
  EXPECT_EQ(r.code, 0) << r.out;
}

TEST_F(RosCli, XacroIsAnsweredWithWhatToDo) {
  const fs::path xacro = root_ / "src" / "franka_description" / "franka_hand.urdf.xacro";
  std::ofstream(xacro) << "<?xml version=\"1.0\"?>\n"
                          "<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\" name=\"hand\">\n"
                          "  <xacro:include filename=\"$(find franka_description)/h.xacro\"/>\n"
                          "  <xacro:franka_hand arm_id=\"panda\"/>\n</robot>\n";
  for (const std::string& cmd :
       {"hand-info " + xacro.string(), "build --object " + realInput("objects/ycb_011_banana.obj") +
                                           " --hand " + xacro.string() + " -o " +
                                           (root_ / "x.h5").string()}) {
    const CliRun r = run(cmd);
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("is a xacro file (ROS macros), not a URDF: expand it first, e.g. `xacro " +
                         xacro.string() + " -o franka_hand.urdf`"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("pip install xacro"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("No link elements"), std::string::npos) << r.out;
  }
}

}  // namespace
