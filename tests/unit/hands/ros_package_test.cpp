// package:// mesh paths resolved through ROS_PACKAGE_PATH and the package that holds the URDF,
// and xacro files refused with what to do (taskmap/hands/ros_package.hpp), on package layouts
// built in a temporary folder.
#include "taskmap/hands/ros_package.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "taskmap/core/error.hpp"
#include "taskmap/hands/hand_model.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

class RosPackageTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::path(::testing::TempDir()) / ("ros_pkg_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    // ws/src/my_desc (package.xml names it "hand_description"), ws/src/plain_pkg (no
    // package.xml), ws/other/deep/a/b/deep_pkg.
    pkg("ws/src/my_desc", "hand_description");
    fs::create_directories(root_ / "ws/src/plain_pkg/meshes");
    fs::create_directories(root_ / "ws/src/my_desc/urdf");
    pkg("ws/other/x/deep_pkg", "deep_pkg");
    if (const char* old = std::getenv("ROS_PACKAGE_PATH")) saved_ = old, had_ = true;
    ::unsetenv("ROS_PACKAGE_PATH");
  }
  void TearDown() override {
    if (had_)
      ::setenv("ROS_PACKAGE_PATH", saved_.c_str(), 1);
    else
      ::unsetenv("ROS_PACKAGE_PATH");
    fs::remove_all(root_);
  }
  void pkg(const std::string& dir, const std::string& name) {
    fs::create_directories(root_ / dir);
    std::ofstream(root_ / dir / "package.xml")
        << "<?xml version=\"1.0\"?>\n<package format=\"3\">\n  <name> " << name
        << " </name>\n  <version>1.0.0</version>\n</package>\n";
  }
  std::string urdf() const { return (root_ / "ws/src/my_desc/urdf/hand.urdf").string(); }
  fs::path root_;
  std::string saved_;
  bool had_ = false;
};

TEST_F(RosPackageTest, TheUrdfsOwnPackageAndItsSiblings) {
  // package.xml's <name>, not the folder name, names the package.
  EXPECT_EQ(resolvePackageUri("package://hand_description/meshes/palm.stl", urdf(), "m "),
            (root_ / "ws/src/my_desc/meshes/palm.stl").string());
  // A sibling package without package.xml, found by its folder name.
  EXPECT_EQ(resolvePackageUri("package://plain_pkg/meshes/f.stl", urdf(), "m "),
            (root_ / "ws/src/plain_pkg/meshes/f.stl").string());
  // Not a package:// URI: unchanged.
  EXPECT_EQ(resolvePackageUri("meshes/palm.stl", urdf(), "m "), "meshes/palm.stl");
}

TEST_F(RosPackageTest, RosPackagePathIsSearchedFirstAndDeep) {
  try {
    resolvePackageUri("package://deep_pkg/m.stl", urdf(), "link 'palm': collision mesh ");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("link 'palm': collision mesh 'package://deep_pkg/m.stl': ROS package "
                       "'deep_pkg' not found (searched ROS_PACKAGE_PATH: not set; and the "
                       "folders above the URDF"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("pass --package-path DIR"), std::string::npos) << msg;
  }
  const std::string path = (root_ / "nothing").string() + ":" + (root_ / "ws/other").string();
  ::setenv("ROS_PACKAGE_PATH", path.c_str(), 1);
  EXPECT_EQ(resolvePackageUri("package://deep_pkg/m.stl", urdf(), "m "),
            (root_ / "ws/other/x/deep_pkg/m.stl").string());
  // An entry that is the package itself.
  ::setenv("ROS_PACKAGE_PATH", (root_ / "ws/other/x/deep_pkg").c_str(), 1);
  EXPECT_EQ(resolvePackageUri("package://deep_pkg/m.stl", urdf(), "m "),
            (root_ / "ws/other/x/deep_pkg/m.stl").string());
}

TEST_F(RosPackageTest, XacroFilesAreRefusedWithWhatToDo) {
  const fs::path xacro = root_ / "ws/src/my_desc/urdf/hand.urdf.xacro";
  std::ofstream(xacro) << "<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\" name=\"h\">\n"
                          "  <xacro:include filename=\"$(find hand_description)/x.xacro\"/>\n"
                          "</robot>\n";
  try {
    HandModel::load(xacro.string());
    FAIL() << "expected an error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("hand URDF '" + xacro.string() +
                       "' is a xacro file (ROS macros), not a URDF: expand it first, e.g. `xacro " +
                       xacro.string() + " -o hand.urdf`"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("hand.hand.json sidecar"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("No link elements"), std::string::npos) << msg;
  }
  // An expanded URDF may keep the xacro namespace and commented-out macros (the Allegro hand's).
  EXPECT_NO_THROW(refuseXacro("hand.urdf",
                              "<robot xmlns:xacro=\"http://www.ros.org/wiki/xacro\" name=\"h\">"
                              "<!-- <xacro:thumb finger_num=\"3\"/> --><link name=\"a\"/></robot>",
                              "hand URDF", true));
  // Xacro content under a .urdf name is recognised too.
  const fs::path named_urdf = root_ / "ws/src/my_desc/urdf/literal.urdf";
  fs::copy_file(xacro, named_urdf);
  EXPECT_THROW(
      {
        try {
          HandModel::load(named_urdf.string());
        } catch (const Error& e) {
          EXPECT_NE(std::string(e.what()).find("is a xacro file"), std::string::npos) << e.what();
          throw;
        }
      },
      Error);
}

}  // namespace
}  // namespace taskmap
