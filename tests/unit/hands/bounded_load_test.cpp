// Meshes parsed in a child process with limits (issue 32): a 3MF that makes assimp abort and a
// tiny .x declaring 250 million vertices are refused with the file and the limit named, the
// calling process unharmed; good meshes come back bit for bit.
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "hostile_meshes.hpp"
#include "hostile_urdf.hpp"
#include "taskmap/core/error.hpp"
#include "taskmap/hands/hand_model.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

class BoundedLoad : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("taskmap_bounded_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string loadError(const std::string& path, double* seconds) {
    const auto t0 = std::chrono::steady_clock::now();
    std::string message = "(loaded)";
    try {
      ObjectModel::load(path);
    } catch (const Error& e) {
      message = e.what();
    }
    *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return message;
  }
  fs::path dir_;
};

TEST_F(BoundedLoad, ThreeMfWithMissingPartIsRefusedNotFatal) {
  const std::string path = (dir_ / "missing_part.3mf").string();
  ASSERT_TRUE(testing::writeMissingPart3mf(path));
  double s = 0;
  const std::string e = loadError(path, &s);
  EXPECT_NE(e.find(path), std::string::npos) << e;
  EXPECT_NE(e, "(loaded)");
  EXPECT_LT(s, 20.0);
  std::printf("3MF with a missing part: %s (%.2f s)\n", e.c_str(), s);
}

TEST_F(BoundedLoad, TinyXDeclaringHugeCountsIsRefusedWithTheLimit) {
  const std::string path = (dir_ / "huge.x").string();
  testing::writeHugeDeclarationX(path);
  EXPECT_LT(fs::file_size(path), 200u);
  double s = 0;
  const std::string e = loadError(path, &s);
  EXPECT_NE(e.find(path), std::string::npos) << e;
  // The same refusal in the sanitizer build, where the child's limit is RLIMIT_DATA.
  EXPECT_NE(e.find("needs more than 256 MiB of memory"), std::string::npos) << e;
  EXPECT_LT(s, 20.0);
  std::printf(".x declaring 250M vertices: %s (%.2f s)\n", e.c_str(), s);
  // This process did not grow by gigabytes.
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  EXPECT_LT(usage.ru_maxrss, 1024 * 1024) << "KiB";
}

// Found by format_fuzz_test (a COLLADA box translated by 2^32 m: float32 keeps no thickness):
// a box whose eight corners collapse onto a plane loses every face to the fin repair and is
// refused, where CGAL crashed on the empty surface.
TEST_F(BoundedLoad, BoxCollapsedOntoAPlaneIsRefusedNotACrash) {
  const std::string path = (dir_ / "flat_box.obj").string();
  std::ofstream(path) << "v -1 0 -1\nv 1 0 -1\nv -1 0 -1\nv 1 0 -1\n"
                         "v -1 0 1\nv 1 0 1\nv -1 0 1\nv 1 0 1\n"
                         "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\n"
                         "f 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n";
  double s = 0;
  const std::string e = loadError(path, &s);
  EXPECT_NE(e.find(path), std::string::npos) << e;
  EXPECT_NE(e.find("no faces are left"), std::string::npos) << e;
}

TEST_F(BoundedLoad, GoodMeshComesBackBitForBit) {
  const std::string box = std::string(TASKMAP_OBJECTS_DIR) + "/mug.obj";
  const ObjectModel child = ObjectModel::load(box);
  ::setenv("TASKMAP_NO_PARSE_CHILD", "1", 1);
  const ObjectModel inline_load = ObjectModel::load(box);
  ::unsetenv("TASKMAP_NO_PARSE_CHILD");
  EXPECT_EQ(child.mesh().vertices, inline_load.mesh().vertices);
  EXPECT_EQ(child.mesh().faces, inline_load.mesh().faces);
}

TEST_F(BoundedLoad, HandLinkMeshThatCrashesAssimpIsRefused) {
  ASSERT_TRUE(testing::writeMissingPart3mf((dir_ / "link.3mf").string()));
  std::string urdf = testing::chainUrdf(1);
  const std::string box = "<box size=\"0.01 0.01 0.01\"/>";
  urdf.replace(urdf.rfind(box), box.size(), "<mesh filename=\"link.3mf\"/>");
  testing::writeText((dir_ / "h.urdf").string(), urdf);
  testing::writeText((dir_ / "h.hand.json").string(), testing::chainSidecar());
  std::string e = "(loaded)";
  try {
    HandModel::load((dir_ / "h.urdf").string());
  } catch (const Error& err) {
    e = err.what();
  }
  EXPECT_NE(e.find("link.3mf"), std::string::npos) << e;
  EXPECT_NE(e, "(loaded)");
}

}  // namespace
}  // namespace taskmap
