// Real hands and real objects through the tool (label cli): hand-info (text, JSON, picture,
// warnings, convex pieces of non-convex link meshes), mesh-info --repair wrap on an open scan,
// and a build that stores no grasp.
#include <gtest/gtest.h>

#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"

namespace {

namespace fs = std::filesystem;

using taskmap::testing::CliRun;

CliRun runCli(const std::string& args) {
  return taskmap::testing::runTaskmap(args);
}

std::string real(const std::string& name) {
  return std::string(TEST_DATA_DIR) + "/real/" + name;
}
const std::string kFranka = real("hands/franka_hand/franka_hand.urdf");

std::string temp(const std::string& name) {
  return ::testing::TempDir() + "/hands_cli_" + std::to_string(::getpid()) + "_" + name;
}

/// A copy of the real Franka hand with a changed sidecar, in its own folder.
std::string frankaWith(const std::string& tag, const std::string& key, const nlohmann::json& v) {
  const fs::path dir = temp(tag);
  fs::create_directories(dir / "meshes" / "collision");
  fs::copy_file(kFranka, dir / "franka_hand.urdf", fs::copy_options::overwrite_existing);
  fs::copy_file(real("hands/franka_hand/meshes/collision/hand.stl"),
                dir / "meshes" / "collision" / "hand.stl", fs::copy_options::overwrite_existing);
  nlohmann::json j =
      nlohmann::json::parse(std::ifstream(real("hands/franka_hand/franka_hand.hand.json")));
  j[key] = v;
  std::ofstream(dir / "franka_hand.hand.json") << j.dump(2);
  return (dir / "franka_hand.urdf").string();
}

TEST(HandsCli, HandInfoTextShowsJointsMimicPalmAndApproach) {
  const CliRun run = runCli("hand-info " + kFranka);
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("hand:           franka_hand (URDF robot 'hand')"), std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("panda_finger_joint1      prismatic [0, 0.04] axis (0, 1, 0)  preshape "
                         "0.04, closed 0"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("mimics panda_finger_joint1: q = 1 q + 0"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("palm frame:     xyz (0, 0, 0.0584) m"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("approach axis:  (0, 0, 1)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("rho:            0.07805 m"), std::string::npos) << run.out;
  EXPECT_EQ(run.out.find("warning:"), std::string::npos) << run.out;
}

TEST(HandsCli, HandInfoJsonAndPicture) {
  const std::string png = temp("allegro.png");
  const CliRun run =
      runCli("hand-info " + real("hands/allegro_right/allegro_hand_description_right.urdf") +
             " --json --png " + png);
  ASSERT_EQ(run.code, 0) << run.out;
  const auto j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j.at("name"), "allegro_hand_right");
  EXPECT_EQ(j.at("closing").size(), 11u);
  EXPECT_EQ(j.at("fingers").at("thumb").size(), 5u);
  int actuated = 0;
  for (const auto& e : j.at("joints")) actuated += e.contains("actuated");
  EXPECT_EQ(actuated, 16);
  EXPECT_TRUE(j.at("warnings").empty());
  // A PNG of 1500 x 1000 pixels (IHDR width and height, big-endian).
  std::ifstream in(png, std::ios::binary);
  std::array<unsigned char, 24> h{};
  in.read(reinterpret_cast<char*>(h.data()), 24);
  ASSERT_TRUE(in.good());
  EXPECT_EQ(h[1], 'P');
  EXPECT_EQ((h[16] << 24 | h[17] << 16 | h[18] << 8 | h[19]), 1500);
  EXPECT_EQ((h[20] << 24 | h[21] << 16 | h[22] << 8 | h[23]), 1000);
  fs::remove(png);
}

TEST(HandsCli, HandInfoWarnsAboutSetUpsThatCannotGrasp) {
  // Approach axis reversed: the fingers close behind the palm.
  CliRun run = runCli("hand-info " + frankaWith("reversed", "approach_axis", {0, 0, -1}));
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("warning:        no finger link reaches in front of the palm"),
            std::string::npos)
      << run.out;
  // Palm frame at the flange: the hand body lies 6.6 cm in front of it.
  run = runCli("hand-info " +
               frankaWith("flange", "palm_frame", {{"xyz", {0, 0, 0}}, {"rpy", {0, 0, 0}}}));
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("warning:        link 'panda_hand' is fixed to the palm and reaches "
                         "0.06596 m in front"),
            std::string::npos)
      << run.out;
}

TEST(HandsCli, BuildThatStoresNoGraspFailsAndSaysWhy) {
  const std::string out = temp("none.h5");
  const CliRun run = runCli("build --object " + real("objects/ycb_011_banana.obj") + " --hand " +
                            frankaWith("backwards", "approach_axis", {0, 0, -1}) + " -o " + out +
                            " --trials 10 --threads 1 -q");
  EXPECT_EQ(run.code, 3) << run.out;
  EXPECT_NE(run.out.find("taskmap build: error: no grasp stored after 10 trials: "),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("approach_axis"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("nothing written to"), std::string::npos) << run.out;
  EXPECT_FALSE(fs::exists(out));
}

TEST(HandsCli, MillimetreBananaIsRefused) {
  // A 9 cm object in millimetres read as metres is 90 m across: below the loader's absolute
  // limit (100 m), 700 times the hand. The banana at --scale 500 stands in for such a file.
  const std::string out = temp("mm.h5");
  const CliRun run = runCli("build --object " + real("objects/ycb_011_banana.obj") +
                            " --scale 500 --hand " + kFranka + " -o " + out + " --trials 10");
  EXPECT_EQ(run.code, 1) << run.out;
  // The file is in metres: the scale that fixes it is 1.
  EXPECT_NE(run.out.find("is the file in metres? scale 1 (--scale 1) makes it 0.194 m across"),
            std::string::npos)
      << run.out;
  EXPECT_FALSE(fs::exists(out));
}

TEST(HandsCli, MeshInfoWrapsAnOpenScan) {
  // The banana with a hole: 40 faces dropped from the OBJ.
  const std::string open = temp("banana_open.obj");
  {
    std::ifstream in(real("objects/ycb_011_banana.obj"));
    std::ofstream o(open);
    std::string line;
    int face = 0;
    while (std::getline(in, line)) {
      if (line.rfind("f ", 0) == 0 && (++face > 5000 && face <= 5040)) continue;
      if (line.rfind("mtllib", 0) == 0 || line.rfind("usemtl", 0) == 0) continue;
      o << line << "\n";
    }
  }
  CliRun run = runCli("mesh-info " + open);
  EXPECT_EQ(run.code, 1) << run.out;
  EXPECT_NE(run.out.find("`--repair wrap`"), std::string::npos) << run.out;
  run = runCli("mesh-info " + open + " --repair wrap --json");
  ASSERT_EQ(run.code, 0) << run.out;
  const auto j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j.at("closed"), true);
  EXPECT_NE(j.at("repairs")[0].get<std::string>().find("alpha wrapping"), std::string::npos);
  EXPECT_NEAR(j.at("volume").get<double>(), 1.715e-4, 0.05e-4);
  run = runCli("mesh-info " + open + " --repair wrap --no-repair");
  EXPECT_NE(run.out.find("contradict"), std::string::npos) << run.out;
  fs::remove(open);
}

std::string hands(const std::string& name) {
  return std::string(TEST_DATA_DIR) + "/hands/" + name;
}

TEST(HandsCli, HandInfoReportsConvexPiecesOfNonConvexMeshes) {
  CliRun run = runCli("hand-info " + hands("decomp_finger.urdf") + " --json");
  ASSERT_EQ(run.code, 0) << run.out;
  const auto j = nlohmann::json::parse(run.out);
  ASSERT_EQ(j.at("collision_meshes").size(), 2u);
  for (const auto& m : j.at("collision_meshes")) {
    EXPECT_TRUE(m.at("decomposed").get<bool>());
    const bool u = m.at("link") == "finger_u";
    EXPECT_EQ(m.at("pieces").get<int>(), u ? 3 : 2) << m.dump();
    EXPECT_NEAR(m.at("pieces_volume").get<double>(), u ? 22e-6 : 14e-6, 1e-12);
    EXPECT_NEAR(m.at("hull_volume").get<double>(), u ? 40e-6 : 23e-6, 1e-12);
  }
  for (const auto& l : j.at("links"))
    if (l.at("name") == "finger_u") {
      EXPECT_EQ(l.at("shapes").get<int>(), 3);
    }
  run = runCli("hand-info " + hands("decomp_finger.urdf"));
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("u_block.obj part 0: 140 faces, 3 convex pieces, 22 / 40 / 22 "
                         "(decomposed)"),
            std::string::npos)
      << run.out;
}

TEST(HandsCli, HandInfoWarnsWhenAMeshCannotBeDecomposed) {
  // The U-shaped block with its last two faces removed: open, and not to be wrapped, so its
  // hull is kept.
  const fs::path dir = temp("open_u");
  fs::create_directories(dir);
  fs::copy_file(hands("decomp_finger.urdf"), dir / "decomp_finger.urdf",
                fs::copy_options::overwrite_existing);
  nlohmann::json sidecar = nlohmann::json::parse(std::ifstream(hands("decomp_finger.hand.json")));
  sidecar["collision"] = {{"wrap", false}};
  std::ofstream(dir / "decomp_finger.hand.json") << sidecar.dump();
  fs::copy_file(hands("l_block.obj"), dir / "l_block.obj", fs::copy_options::overwrite_existing);
  std::ifstream in(hands("u_block.obj"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  lines.resize(lines.size() - 2);
  std::ofstream out(dir / "u_block.obj");
  for (const auto& line : lines) out << line << "\n";
  out.close();
  const CliRun run = runCli("hand-info " + (dir / "decomp_finger.urdf").string());
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("warning:        URDF '" + (dir / "decomp_finger.urdf").string() +
                         "': link 'finger_u': collision mesh 'u_block.obj' (a connected part) "
                         "is not closed (it has border edges); its convex hull is used"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("u_block.obj part 0: 138 faces, 1 convex piece"), std::string::npos)
      << run.out;
  fs::remove_all(dir);
}

}  // namespace
