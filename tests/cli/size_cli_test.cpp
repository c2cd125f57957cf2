// The size check that knows the hand (label cli): the YCB banana written in centimetres and in
// millimetres is refused in under a second with the --scale that fixes it, the banana in metres
// is built, --allow-size builds anyway and the no-grasp message then names the size first;
// mesh-info flags sizes implausible for a graspable object.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "cpu_time.hpp"
#include "scratch_dir.hpp"

namespace {

namespace fs = std::filesystem;

using taskmap::testing::CliRun;
using taskmap::testing::realInput;
using taskmap::testing::runTaskmap;
const taskmap::testing::ScratchDir kScratch("size_cli");

const std::string kBanana = realInput("objects/ycb_011_banana.obj");
const std::string kFranka = realInput("hands/franka_hand/franka_hand.urdf");

/// The banana with every vertex multiplied by `factor` (a file in other units), no materials.
std::string scaledBanana(double factor, const std::string& tag) {
  const std::string path = kScratch.path(tag + ".obj");
  std::ifstream in(kBanana);
  std::ofstream out(path);
  out.precision(10);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("mtllib", 0) == 0 || line.rfind("usemtl", 0) == 0) continue;
    if (line.rfind("v ", 0) == 0) {
      std::istringstream v(line.substr(2));
      double x = 0, y = 0, z = 0;
      v >> x >> y >> z;
      out << "v " << x * factor << " " << y * factor << " " << z * factor << "\n";
    } else {
      out << line << "\n";
    }
  }
  return path;
}

/// Runs a command and its wall time in seconds.
CliRun timed(const std::string& args, double* seconds) {
  const double t0 = taskmap::testing::cpuSeconds(RUSAGE_CHILDREN);
  CliRun run = runTaskmap(args);
  *seconds = taskmap::testing::cpuSeconds(RUSAGE_CHILDREN) - t0;
  return run;
}

TEST(SizeCli, CentimetreBananaIsRefusedInUnderASecondWithTheScaleThatFixesIt) {
  const std::string cm = scaledBanana(100.0, "cm");
  const std::string out = kScratch.path("cm.h5");
  double seconds = 0;
  const CliRun run =
      timed("build --object " + cm + " --hand " + kFranka + " -o " + out + " -q", &seconds);
  EXPECT_EQ(run.code, 1) << run.out;
  EXPECT_LT(seconds, 1.0) << run.out;
  EXPECT_NE(run.out.find("is too large for the hand: the object is 17.8 m across (bounding box "),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("times the 0.1"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("is the file in centimetres? scale 0.01 (--scale 0.01) makes it 0.178 m "
                         "across"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("--allow-size"), std::string::npos) << run.out;
  EXPECT_FALSE(fs::exists(out));

  // The scale it names fixes it: the same file with --scale 0.01 passes the check.
  const CliRun fixed = runTaskmap("build --object " + cm + " --scale 0.01 --hand " + kFranka +
                                  " -o " + out + " -q --valid 1 --trials 64 --threads 1");
  EXPECT_EQ(fixed.out.find("too large"), std::string::npos) << fixed.out;
  EXPECT_NE(fixed.code, 1) << fixed.out;
  fs::remove(out);

  // --allow-size builds it as it is; with no grasp, the message names the size first.
  const CliRun allowed = runTaskmap("build --object " + cm + " --hand " + kFranka + " -o " + out +
                                    " -q --allow-size --trials 4 --threads 1");
  EXPECT_EQ(allowed.code, 3) << allowed.out;
  EXPECT_NE(allowed.out.find("no grasp stored after 4 trials: first suspect, the size: the object "
                             "is 17.8 m across"),
            std::string::npos)
      << allowed.out;
  EXPECT_NE(allowed.out.find("--scale 0.01"), std::string::npos) << allowed.out;
  EXPECT_FALSE(fs::exists(out));
  fs::remove(cm);
}

TEST(SizeCli, MillimetreBananaIsRefusedInUnderASecondWithTheScaleThatFixesIt) {
  // 194 m across: above the loader's absolute limit (100 m), refused while loading.
  const std::string mm = scaledBanana(1000.0, "mm");
  const std::string out = kScratch.path("mm.h5");
  double seconds = 0;
  CliRun run =
      timed("build --object " + mm + " --hand " + kFranka + " -o " + out + " -q", &seconds);
  EXPECT_EQ(run.code, 1) << run.out;
  EXPECT_LT(seconds, 1.0) << run.out;
  EXPECT_NE(run.out.find("is the file in millimetres? scale 0.001 (--scale 0.001) makes it "
                         "0.178 m across"),
            std::string::npos)
      << run.out;
  EXPECT_FALSE(fs::exists(out));
  // mesh-info says the same.
  run = runTaskmap("mesh-info " + mm);
  EXPECT_EQ(run.code, 1) << run.out;
  EXPECT_NE(run.out.find("--scale 0.001"), std::string::npos) << run.out;
  // Read at --scale 0.1 it is 17.8 m: below the loader's limit, refused by the build's check,
  // which names the scale of the file's unit.
  run = timed("build --object " + mm + " --scale 0.1 --hand " + kFranka + " -o " + out + " -q",
              &seconds);
  EXPECT_EQ(run.code, 1) << run.out;
  EXPECT_LT(seconds, 1.0) << run.out;
  EXPECT_NE(run.out.find("is the file in millimetres? scale 0.001 (--scale 0.001)"),
            std::string::npos)
      << run.out;
  fs::remove(mm);
}

TEST(SizeCli, BananaInMetresIsBuilt) {
  const std::string out = kScratch.path("m.h5");
  const CliRun run = runTaskmap("build --object " + kBanana + " --hand " + kFranka + " -o " + out +
                                " -q --valid 1 --trials 200 --threads 1 --hold-test off");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_EQ(run.out.find("too large"), std::string::npos) << run.out;
  EXPECT_TRUE(fs::exists(out));
  fs::remove(out);
}

TEST(SizeCli, MeshInfoFlagsSizesImplausibleForAGraspableObject) {
  // A 1 m cube (1 m^3).
  const std::string cube = kScratch.path("cube.obj");
  {
    std::ofstream o(cube);
    for (int i = 0; i < 8; ++i)
      o << "v " << (i & 1) << " " << ((i >> 1) & 1) << " " << ((i >> 2) & 1) << "\n";
    o << "f 1 3 2\nf 2 3 4\nf 5 6 7\nf 6 8 7\nf 1 2 5\nf 2 6 5\n"
         "f 3 7 4\nf 4 7 8\nf 1 5 3\nf 3 5 7\nf 2 4 6\nf 4 8 6\n";
  }
  CliRun run = runTaskmap("mesh-info " + cube);
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("warning:        the object is 1 m across: large for a graspable object"),
            std::string::npos)
      << run.out;
  // Centimetres and inches both give a hand-held size; both are named.
  EXPECT_NE(run.out.find("--scale 0.01"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("--scale 0.0254"), std::string::npos) << run.out;
  run = runTaskmap("mesh-info " + cube + " --json");
  ASSERT_EQ(run.code, 0) << run.out;
  auto j = nlohmann::json::parse(run.out);
  EXPECT_FALSE(j.at("graspable_size").get<bool>());
  EXPECT_EQ(j.at("warnings").size(), 1u);
  // Read at --scale 0.1 it is 10 cm: no warning.
  run = runTaskmap("mesh-info " + cube + " --scale 0.1 --json");
  ASSERT_EQ(run.code, 0) << run.out;
  j = nlohmann::json::parse(run.out);
  EXPECT_TRUE(j.at("graspable_size").get<bool>());
  EXPECT_TRUE(j.at("warnings").empty());
  // The centimetre banana: flagged with the scale of centimetres.
  const std::string cm = scaledBanana(100.0, "cm_info");
  run = runTaskmap("mesh-info " + cm);
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("the object is 17.8 m across: large for a graspable object"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("is the file in centimetres? scale 0.01 (--scale 0.01)"),
            std::string::npos)
      << run.out;
  // The banana itself: size shown, no warning.
  run = runTaskmap("mesh-info " + kBanana);
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("size:           "), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("warning:"), std::string::npos) << run.out;
  fs::remove(cube);
  fs::remove(cm);
}

}  // namespace
