// MJCF hands through the tool (issue 52, label cli): the LEAP hand as MuJoCo Menagerie publishes
// it (tests/data/real/hands/leap_hand_mjcf) in hand-info, hand-init, build, inspect, validate
// (its own dynamics recorded, or the protocol's), view, export and dataset; an MJCF file
// taskmap cannot use refused with its line; the same hand as URDF and as MJCF giving the same
// map (the recorded hand path and file hash aside).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "map_compare.hpp"
#include "scratch_dir.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace {

namespace fs = std::filesystem;

using taskmap::testing::realInput;
using taskmap::testing::runTaskmap;
const taskmap::testing::ScratchDir kScratch("mjcf_cli");

const std::string kLeap = realInput("hands/leap_hand_mjcf/right_hand.xml");
const std::string kBanana = realInput("objects/ycb_011_banana.obj");

std::string bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// A copy of the LEAP hand (model, collision meshes, no sidecar) in its own folder.
std::string leapCopy(const std::string& tag) {
  const fs::path dir = kScratch.path(tag);
  fs::create_directories(dir / "assets");
  for (const char* f : {"right_hand.xml", "assets/tip.obj", "assets/thumb_tip.obj"})
    fs::copy_file(realInput(std::string("hands/leap_hand_mjcf/") + f), dir / f,
                  fs::copy_options::overwrite_existing);
  return (dir / "right_hand.xml").string();
}

TEST(MjcfCli, HandInfoReportsTheLeapHand) {
  const auto run = runTaskmap("hand-info --json " + kLeap);
  ASSERT_EQ(run.code, 0) << run.out;
  const auto j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["format"], "MJCF");
  EXPECT_EQ(j["robot_name"], "leap_rh");
  EXPECT_EQ(j["joints"].size(), 16u);
  EXPECT_EQ(j["model_warnings"].size(), 8u);  // the visual meshes not copied
  EXPECT_EQ(j["stated_dynamics"]["masses"], 17);
  EXPECT_EQ(j["stated_dynamics"]["servo_gains"], 16);
  EXPECT_EQ(j["stated_dynamics"]["contact_excludes"], 18);
  EXPECT_TRUE(j["warnings"].empty()) << j["warnings"];
  const auto text = runTaskmap("hand-info " + kLeap);
  ASSERT_EQ(text.code, 0) << text.out;
  EXPECT_NE(text.out.find("mjcf:"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("dynamics:       the model states 17 of 17 masses"), std::string::npos)
      << text.out;
  EXPECT_NE(text.out.find("palm_right.obj' is missing"), std::string::npos) << text.out;
}

TEST(MjcfCli, HandInitDraftsASidecarThatLoads) {
  const std::string hand = leapCopy("init");
  const std::string sidecar = (fs::path(hand).parent_path() / "right_hand.hand.json").string();
  const auto init = runTaskmap("hand-init " + hand + " -o " + sidecar);
  ASSERT_EQ(init.code, 0) << init.out;
  EXPECT_NE(init.out.find("guess: palm_link \"palm\""), std::string::npos) << init.out;
  const auto info = runTaskmap("hand-info --json " + hand);
  ASSERT_EQ(info.code, 0) << info.out;
  EXPECT_EQ(nlohmann::json::parse(info.out)["palm_link"], "palm");
}

TEST(MjcfCli, TheLeapHandBuildsValidatesAndIsShown) {
  const std::string map = kScratch.path("leap_banana.h5");
  const auto build = runTaskmap("build --object " + kBanana + " --hand " + kLeap +
                                " --valid 12 --seed 1 --hold-test off -o " + map);
  ASSERT_EQ(build.code, 0) << build.out;
  EXPECT_NE(build.out.find("hand leap_hand_right"), std::string::npos) << build.out;
  const auto inspect = runTaskmap("inspect --json " + map);
  ASSERT_EQ(inspect.code, 0) << inspect.out;
  EXPECT_EQ(nlohmann::json::parse(inspect.out)["grasps"]["count"], 12);
  // The hand's own dynamics, recorded in /validation params; --protocol-dynamics the protocol's.
  for (const bool stated : {true, false}) {
    const std::string out = kScratch.path(stated ? "stated.h5" : "protocol.h5");
    const auto v = runTaskmap("validate " + map + " --grasps 2 --threads 2 -o " + out +
                              (stated ? "" : " --protocol-dynamics"));
    ASSERT_EQ(v.code, 0) << v.out;
    const taskmap::TaskMapData m = taskmap::readMap(out);
    ASSERT_TRUE(m.validation);
    const auto params = nlohmann::json::parse(m.validation->params_json);
    const auto& d = params["hand_dynamics"];
    EXPECT_EQ(d["source"], "MJCF");
    EXPECT_EQ(d["kp"]["model"], stated ? 16 : 0);
    EXPECT_EQ(d["mass_inertia"]["model"], stated ? 17 : 0);
    EXPECT_EQ(d["geom_friction"]["of"], 71);
  }
  const std::string page = kScratch.path("leap.html"), glb = kScratch.path("leap.glb");
  const auto view = runTaskmap("view " + map + " -o " + page);
  ASSERT_EQ(view.code, 0) << view.out;
  EXPECT_GT(fs::file_size(page), 10000u);
  const auto exported = runTaskmap("export " + map + " --format glb -o " + glb);
  ASSERT_EQ(exported.code, 0) << exported.out;
  EXPECT_EQ(bytes(glb).substr(0, 4), "glTF");
}

TEST(MjcfCli, ABuildThatTestsItsGraspsRecordsTheHandsDynamics) {
  const std::string map = kScratch.path("leap_tested.h5");
  const auto build = runTaskmap("build --object " + kBanana + " --hand " + kLeap +
                                " --valid 2 --seed 1 --hold-test nominal -o " + map);
  ASSERT_EQ(build.code, 0) << build.out;
  const taskmap::TaskMapData m = taskmap::readMap(map);
  ASSERT_TRUE(m.validation);
  const auto d = nlohmann::json::parse(m.validation->params_json)["hand_dynamics"];
  EXPECT_EQ(d["source"], "MJCF") << m.validation->params_json;
  EXPECT_EQ(d["kp"]["model"], 16);
  EXPECT_EQ(d["mass_inertia"]["model"], 17);
}

TEST(MjcfCli, ADataSetTakesAnMjcfHand) {
  const fs::path dir = kScratch.path("dataset");
  fs::create_directories(dir);
  std::ofstream(dir / "objects.txt") << kBanana << "\n";
  const auto run =
      runTaskmap("dataset --objects " + (dir / "objects.txt").string() + " --hands " + kLeap +
                 " --valid 5 --seed 1 --hold-test off -o " + (dir / "out").string());
  ASSERT_EQ(run.code, 0) << run.out;
  const auto manifest = nlohmann::json::parse(std::ifstream(dir / "out" / "manifest.json"));
  ASSERT_EQ(manifest["jobs"].size(), 1u) << manifest.dump();
  EXPECT_EQ(manifest["jobs"][0]["status"], "complete") << manifest.dump();
  EXPECT_EQ(manifest["jobs"][0]["hand"], kLeap);
  EXPECT_TRUE(fs::exists(dir / "out" / "ycb_011_banana__right_hand.h5"));
}

TEST(MjcfCli, AnUnusableMjcfIsRefusedWithItsLine) {
  const std::string hand = kScratch.path("ball.xml");
  std::ofstream(hand) << "<mujoco>\n<worldbody>\n<body name=\"p\">\n<geom size=\"0.01\"/>\n"
                         "<body name=\"f\">\n<joint name=\"b\" type=\"ball\"/>\n</body>\n</body>\n"
                         "</worldbody>\n</mujoco>\n";
  const auto run = runTaskmap("hand-info " + hand);
  EXPECT_NE(run.code, 0);
  EXPECT_NE(run.out.find(hand + "': <joint name='b'> at line 6: ball joints"), std::string::npos)
      << run.out;
}

// Issue 52 item 3: the Barrett hand as URDF and as MJCF (tests/data/hands/barrett_mjcf) builds
// the same map: every stored value equal but the two that name the model file (the hand path in
// /sampling params_json, the file's SHA-256 in /hand); with those two made equal, the maps
// written by one writer are the same bytes.
TEST(MjcfCli, TheSameHandAsUrdfAndMjcfBuildsTheSameMap) {
  const std::string urdf = std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf";
  const std::string mjcf = std::string(TEST_DATA_DIR) + "/hands/barrett_mjcf/barrett.xml";
  const std::string object = std::string(TASKMAP_OBJECTS_DIR) + "/cylinder.obj";
  const std::string a = kScratch.path("urdf.h5"), b = kScratch.path("mjcf.h5");
  for (const auto& [hand, out] : {std::pair{urdf, a}, std::pair{mjcf, b}}) {
    const auto run = runTaskmap("build --object " + object + " --hand " + hand +
                                " --valid 200 --seed 3 --threads 2 --hold-test off -o " + out);
    ASSERT_EQ(run.code, 0) << run.out;
  }
  const taskmap::TaskMapData from_urdf = taskmap::readMap(a);
  taskmap::TaskMapData from_mjcf = taskmap::readMap(b);
  EXPECT_NE(from_mjcf.hand.urdf_sha256, from_urdf.hand.urdf_sha256);
  EXPECT_GE(from_mjcf.grasps.size(), 200u);
  auto params = nlohmann::json::parse(from_mjcf.sampling.params_json);
  EXPECT_EQ(params["hand"], mjcf);
  params["hand"] = urdf;
  from_mjcf.sampling.params_json = params.dump();
  from_mjcf.hand.urdf_sha256 = from_urdf.hand.urdf_sha256;
  taskmap::testing::expectSameMapContent(from_urdf, from_mjcf, true);
  EXPECT_EQ(from_mjcf.hand.link_names, from_urdf.hand.link_names);
  const std::string a2 = kScratch.path("urdf_rewritten.h5"),
                    b2 = kScratch.path("mjcf_rewritten.h5");
  taskmap::writeMap(a2, from_urdf);
  taskmap::writeMap(b2, from_mjcf);
  EXPECT_TRUE(bytes(a2) == bytes(b2)) << "the rewritten maps differ";
}

}  // namespace
