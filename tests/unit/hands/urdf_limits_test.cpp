// Hand URDFs (issue 32): iterative tree walk (long chains in linear time), size and XML depth
// checked before TinyXML parses, joints that do not form a tree refused, FIFOs refused.
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "cpu_time.hpp"
#include "hostile_urdf.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/core/xml_scan.hpp"
#include "taskmap/hands/hand_model.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

class HandUrdfLimits : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("taskmap_urdf_limits_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // Writes hand <name>.urdf with the chain sidecar; returns the URDF path.
  std::string hand(const std::string& name, const std::string& urdf) const {
    testing::writeText((dir_ / (name + ".urdf")).string(), urdf);
    testing::writeText((dir_ / (name + ".hand.json")).string(), testing::chainSidecar());
    return (dir_ / (name + ".urdf")).string();
  }
  // The error of loading path (fails the test when it loads), and the seconds it took.
  static std::string loadError(const std::string& path, double* seconds) {
    const double t0 = testing::cpuSeconds();
    std::string message = "(loaded)";
    try {
      HandModel::load(path);
    } catch (const Error& e) {
      message = e.what();
    }
    *seconds = testing::cpuSeconds() - t0;
    return message;
  }
  fs::path dir_;
};

TEST_F(HandUrdfLimits, LongChainLoadsInLinearTime) {
  const std::string path = hand("chain", testing::chainUrdf(kMaxHandLinks - 1));
  const double t0 = testing::cpuSeconds();
  const HandModel h = HandModel::load(path);
  const double s = testing::cpuSeconds() - t0;
  EXPECT_EQ(h.links().size(), kMaxHandLinks);
  EXPECT_EQ(h.links().back().name, "l" + std::to_string(kMaxHandLinks - 1));
  EXPECT_LT(s, 1.0);
  std::printf("chain of %zu links loaded in %.3f s\n", kMaxHandLinks, s);
}

TEST_F(HandUrdfLimits, HugeChainIsRefusedBeforeParsing) {
  double s = 0;
  const std::string path = hand("huge", testing::chainUrdf(100000));
  const std::string e = loadError(path, &s);
  EXPECT_NE(e.find(path), std::string::npos) << e;
  EXPECT_NE(e.find("limit of 256"), std::string::npos) << e;
  EXPECT_LT(s, 1.0);
  std::printf("100,000-link chain refused in %.3f s\n", s);
}

TEST_F(HandUrdfLimits, DeeplyNestedXmlIsRefusedBeforeTinyXml) {
  double s = 0;
  const std::string path = hand("deep", testing::deepUrdf(100000));
  const std::string e = loadError(path, &s);
  EXPECT_NE(e.find(path), std::string::npos) << e;
  EXPECT_NE(e.find("nested more than 64"), std::string::npos) << e;
  EXPECT_LT(s, 1.0);
}

TEST_F(HandUrdfLimits, DetachedCycleIsRefused) {
  double s = 0;
  const std::string path = hand("cycle", testing::detachedCycleUrdf());
  const std::string e = loadError(path, &s);
  EXPECT_NE(e.find(path), std::string::npos) << e;
  EXPECT_NE(e.find("c1"), std::string::npos) << e;
}

TEST_F(HandUrdfLimits, FifoUrdfAndSidecarAreRefused) {
  const std::string urdf = (dir_ / "pipe.urdf").string();
  ASSERT_EQ(::mkfifo(urdf.c_str(), 0600), 0);
  double s = 0;
  std::string e = loadError(urdf, &s);
  EXPECT_NE(e.find("FIFO"), std::string::npos) << e;
  EXPECT_NE(e.find(urdf), std::string::npos) << e;
  testing::writeText((dir_ / "ok.urdf").string(), testing::chainUrdf(2));
  const std::string sidecar = (dir_ / "ok.hand.json").string();
  ASSERT_EQ(::mkfifo(sidecar.c_str(), 0600), 0);
  e = loadError((dir_ / "ok.urdf").string(), &s);
  EXPECT_NE(e.find("FIFO"), std::string::npos) << e;
  EXPECT_NE(e.find(sidecar), std::string::npos) << e;
}

TEST(XmlScan, CountsDepthAndSkipsCommentsAndQuotes) {
  const XmlShape s = scanXml(
      "<?xml version=\"1.0\"?><!-- <a><b><c> --><robot a=\"x>y\"><link name='l'/>"
      "<joint name=\"j\"><parent link=\"l\"/></joint><![CDATA[<x><y>]]></robot>");
  EXPECT_EQ(s.max_depth, 2);
  EXPECT_EQ(s.links, 1u);
  EXPECT_EQ(s.joints, 1u);
}

}  // namespace
}  // namespace taskmap
