// Real hands and real objects through the tool (label cli): hand-info (text, JSON, picture,
// warnings, convex pieces of non-convex link meshes), mesh-info --repair wrap on an open scan,
// and a build that stores no grasp.
#include <gtest/gtest.h>

#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "scratch_dir.hpp"

namespace {

namespace fs = std::filesystem;

using taskmap::testing::CliRun;
using taskmap::testing::realInput;
using taskmap::testing::runTaskmap;
const taskmap::testing::ScratchDir kScratch("hands_cli");

const std::string kFranka = realInput("hands/franka_hand/franka_hand.urdf");

/// A copy of the real Franka hand with a changed sidecar, in its own folder.
std::string frankaWith(const std::string& tag, const std::string& key, const nlohmann::json& v) {
  const fs::path dir = kScratch.path(tag);
  fs::create_directories(dir / "meshes" / "collision");
  fs::copy_file(kFranka, dir / "franka_hand.urdf", fs::copy_options::overwrite_existing);
  fs::copy_file(realInput("hands/franka_hand/meshes/collision/hand.stl"),
                dir / "meshes" / "collision" / "hand.stl", fs::copy_options::overwrite_existing);
  nlohmann::json j =
      nlohmann::json::parse(std::ifstream(realInput("hands/franka_hand/franka_hand.hand.json")));
  j[key] = v;
  std::ofstream(dir / "franka_hand.hand.json") << j.dump(2);
  return (dir / "franka_hand.urdf").string();
}

/// A copy of the real Franka hand as the xacro literal gives it (franka_ros, gazebo=false,
/// safety_distance=0.03): the self-collision link panda_hand_sc (two capsules inflated by 3 cm)
/// fixed to the palm, reaching past the fingers.
std::string frankaWithSelfCollisionLink() {
  const std::string urdf = frankaWith("sc", "description", "with panda_hand_sc");
  std::ifstream in(urdf);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  std::string capsules;
  for (const auto& [z, r] : {std::pair<double, double>{0.04, 0.07}, {0.10, 0.05}}) {
    const std::string zs = std::to_string(z), rs = std::to_string(r);
    capsules += "<collision><origin xyz=\"0 0 " + zs +
                "\" rpy=\"1.5707963 0 0\"/><geometry><cylinder radius=\"" + rs +
                "\" length=\"0.1\"/></geometry></collision>";
    for (const char* y : {"0.05", "-0.05"})
      capsules += "<collision><origin xyz=\"0 " + std::string(y) + " " + zs +
                  "\"/><geometry><sphere radius=\"" + rs + "\"/></geometry></collision>";
  }
  const std::string link = "<link name=\"panda_hand_sc\">" + capsules +
                           "</link><joint name=\"panda_hand_sc_joint\" type=\"fixed\"><parent "
                           "link=\"panda_hand\"/><child link=\"panda_hand_sc\"/></joint>";
  text.insert(text.rfind("</robot>"), link + "\n");
  std::ofstream(urdf) << text;
  return urdf;
}

// hand-init drafts the sidecar from the URDF alone, prints each guess, refuses to replace a
// file, and the draft builds a map of the YCB banana without edits (real Franka and Allegro).
TEST(HandsCli, HandInitDraftBuildsAMapWithoutEdits) {
  const std::string allegro = realInput("hands/allegro_right/allegro_hand_description_right.urdf");
  for (const std::string& urdf : {kFranka, allegro}) {
    const fs::path dir = kScratch.path("init_" + fs::path(urdf).stem().string());
    fs::create_directories(dir);
    fs::copy(fs::path(urdf).parent_path(), dir,
             fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    const std::string stem = fs::path(urdf).stem().string();
    const std::string copy = (dir / (stem + ".urdf")).string();
    const std::string sidecar = (dir / (stem + ".hand.json")).string();
    fs::remove(sidecar);  // the user's sidecar is what hand-init replaces
    CliRun r = runTaskmap("hand-init " + copy + " -o " + sidecar);
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("guess: palm_link"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("closes toward"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("guess: finger"), std::string::npos) << r.out;
    ASSERT_TRUE(fs::exists(sidecar));
    r = runTaskmap("hand-init " + copy + " -o " + sidecar);
    EXPECT_NE(r.code, 0);
    EXPECT_NE(r.out.find("give --force"), std::string::npos) << r.out;
    const std::string map = kScratch.path("init_" + stem + ".h5");
    r = runTaskmap("build --object " + realInput("objects/ycb_011_banana.obj") + " --hand " + copy +
                   " --valid 20 --trials 20000 --seed 1 --hold-test off --quiet -o " + map);
    EXPECT_EQ(r.code, 0) << stem << ": " << r.out;
    EXPECT_TRUE(fs::exists(map)) << stem;
  }
  // Without -o the draft is printed.
  const CliRun printed = runTaskmap("hand-init " + kFranka);
  ASSERT_EQ(printed.code, 0) << printed.out;
  EXPECT_NE(printed.out.find("\"palm_link\": \"panda_hand\""), std::string::npos) << printed.out;
}

TEST(HandsCli, HandInfoTextShowsJointsMimicPalmAndApproach) {
  const CliRun run = runTaskmap("hand-info " + kFranka);
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
  const std::string png = kScratch.path("allegro.png");
  const CliRun run = runTaskmap(
      "hand-info " + realInput("hands/allegro_right/allegro_hand_description_right.urdf") +
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
  CliRun run = runTaskmap("hand-info " + frankaWith("reversed", "approach_axis", {0, 0, -1}));
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("warning:        no finger link reaches in front of the palm"),
            std::string::npos)
      << run.out;
  // The inflated self-collision link of the xacro literal reaches past the fingers: warned,
  // and the build prints the same warning before its trials, which store no grasp.
  const std::string sc = frankaWithSelfCollisionLink();
  run = runTaskmap("hand-info " + sc);
  ASSERT_EQ(run.code, 0) << run.out;
  const std::string sc_warning =
      "link 'panda_hand_sc' is fixed to the palm and reaches 0.0916 m in front of the palm frame "
      "along the approach axis, as far as or beyond every finger (farthest 0.0545 m while "
      "closing)";
  EXPECT_NE(run.out.find("warning:        " + sc_warning), std::string::npos) << run.out;
  const std::string out = kScratch.path("sc.h5");
  run = runTaskmap("build --object " + realInput("objects/ycb_011_banana.obj") + " --hand " + sc +
                   " -o " + out + " --trials 20 --threads 1 -q");
  EXPECT_EQ(run.code, 3) << run.out;
  const auto warned = run.out.find("taskmap build: warning: hand 'franka_hand': " + sc_warning);
  EXPECT_NE(warned, std::string::npos) << run.out;
  EXPECT_LT(warned, run.out.find("no grasp stored")) << run.out;
  EXPECT_FALSE(fs::exists(out));
}

TEST(HandsCli, PalmFrameBehindThePalmIsANoteNotAWarning) {
  // Palm frame at the flange: the hand body lies 6.6 cm in front of it, the fingers 11.3 cm;
  // the palm touches objects and the hand grasps (a note, no warning; the build is quiet).
  const std::string flange =
      frankaWith("flange", "palm_frame", {{"xyz", {0, 0, 0}}, {"rpy", {0, 0, 0}}});
  CliRun run = runTaskmap("hand-info " + flange);
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("note:           link 'panda_hand' is fixed to the palm and reaches "
                         "0.06596 m in front"),
            std::string::npos)
      << run.out;
  EXPECT_EQ(run.out.find("warning:"), std::string::npos) << run.out;
  const std::string out = kScratch.path("flange.h5");
  run =
      runTaskmap("build --object " + realInput("objects/ycb_011_banana.obj") + " --hand " + flange +
                 " -o " + out + " --valid 1 --trials 200 --threads 1 --hold-test off -q");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_EQ(run.out.find("warning"), std::string::npos) << run.out;
  fs::remove(out);
  // The real hand as checked in: no warning from hand-info or build.
  run =
      runTaskmap("build --object " + realInput("objects/ycb_011_banana.obj") + " --hand " +
                 kFranka + " -o " + out + " --valid 1 --trials 200 --threads 1 --hold-test off -q");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_EQ(run.out.find("warning"), std::string::npos) << run.out;
  fs::remove(out);
}

TEST(HandsCli, BuildThatStoresNoGraspFailsAndSaysWhy) {
  const std::string out = kScratch.path("none.h5");
  const CliRun run = runTaskmap("build --object " + realInput("objects/ycb_011_banana.obj") +
                                " --hand " + frankaWith("backwards", "approach_axis", {0, 0, -1}) +
                                " -o " + out + " --trials 10 --threads 1 -q");
  EXPECT_EQ(run.code, 3) << run.out;
  // hand-info's warning first, before the trials.
  EXPECT_NE(run.out.find("taskmap build: warning: hand 'franka_hand': no finger link reaches in "
                         "front of the palm"),
            std::string::npos)
      << run.out;
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
  const std::string out = kScratch.path("mm.h5");
  const CliRun run = runTaskmap("build --object " + realInput("objects/ycb_011_banana.obj") +
                                " --scale 500 --hand " + kFranka + " -o " + out + " --trials 10");
  EXPECT_EQ(run.code, 1) << run.out;
  // The file is in metres: the scale that fixes it is 1.
  EXPECT_NE(run.out.find("is the file in metres? scale 1 (--scale 1) makes it 0.178 m across"),
            std::string::npos)
      << run.out;
  EXPECT_FALSE(fs::exists(out));
}

TEST(HandsCli, MeshInfoWrapsAnOpenScan) {
  // The banana with a hole: 40 faces dropped from the OBJ.
  const std::string open = kScratch.path("banana_open.obj");
  {
    std::ifstream in(realInput("objects/ycb_011_banana.obj"));
    std::ofstream o(open);
    std::string line;
    int face = 0;
    while (std::getline(in, line)) {
      if (line.rfind("f ", 0) == 0 && (++face > 5000 && face <= 5040)) continue;
      if (line.rfind("mtllib", 0) == 0 || line.rfind("usemtl", 0) == 0) continue;
      o << line << "\n";
    }
  }
  CliRun run = runTaskmap("mesh-info " + open);
  EXPECT_EQ(run.code, 1) << run.out;
  EXPECT_NE(run.out.find("`--repair wrap`"), std::string::npos) << run.out;
  run = runTaskmap("mesh-info " + open + " --repair wrap --json");
  ASSERT_EQ(run.code, 0) << run.out;
  const auto j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j.at("closed"), true);
  EXPECT_NE(j.at("repairs")[0].get<std::string>().find("alpha wrapping"), std::string::npos);
  EXPECT_NEAR(j.at("volume").get<double>(), 1.715e-4, 0.05e-4);
  run = runTaskmap("mesh-info " + open + " --repair wrap --no-repair");
  EXPECT_NE(run.out.find("contradict"), std::string::npos) << run.out;
  fs::remove(open);
}

std::string hands(const std::string& name) {
  return std::string(TEST_DATA_DIR) + "/hands/" + name;
}

TEST(HandsCli, HandInfoReportsConvexPiecesOfNonConvexMeshes) {
  CliRun run = runTaskmap("hand-info " + hands("decomp_finger.urdf") + " --json");
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
  run = runTaskmap("hand-info " + hands("decomp_finger.urdf"));
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("u_block.obj part 0: 140 faces, 3 convex pieces, 22 / 40 / 22 "
                         "(decomposed)"),
            std::string::npos)
      << run.out;
}

TEST(HandsCli, HandInfoWarnsWhenAMeshCannotBeDecomposed) {
  // The U-shaped block with its last two faces removed: open, and not to be wrapped, so its
  // hull is kept.
  const fs::path dir = kScratch.path("open_u");
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
  const CliRun run = runTaskmap("hand-info " + (dir / "decomp_finger.urdf").string());
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("warning:        URDF '" + (dir / "decomp_finger.urdf").string() +
                         "': link 'finger_u': collision mesh 'u_block.obj' (a connected part) "
                         "is not closed (it has border edges); its convex hull is used"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("u_block.obj part 0: 138 faces, 1 convex piece"), std::string::npos)
      << run.out;
  // build prints it before its trials; the same hand with its closed mesh warns of nothing.
  const std::string object = std::string(TASKMAP_OBJECTS_DIR) + "/cylinder.obj";
  CliRun build =
      runTaskmap("build --object " + object + " --hand " + (dir / "decomp_finger.urdf").string() +
                 " -o " + (dir / "m.h5").string() + " --trials 2 --threads 1 -q");
  EXPECT_NE(build.out.find("taskmap build: warning: hand '"), std::string::npos) << build.out;
  EXPECT_NE(build.out.find("is not closed (it has border edges); its convex hull is used"),
            std::string::npos)
      << build.out;
  build = runTaskmap("build --object " + object + " --hand " + hands("decomp_finger.urdf") +
                     " -o " + (dir / "m.h5").string() + " --trials 2 --threads 1 -q");
  EXPECT_EQ(build.out.find("warning"), std::string::npos) << build.out;
  fs::remove_all(dir);
}

}  // namespace

namespace {

TEST(HandsCli, UnknownHandAndObjectNamesGetDidYouMean) {
  const std::string objects = TASKMAP_OBJECTS_DIR;
  const std::string out = kScratch.path("dym.h5");
  CliRun run = runTaskmap("build --object " + objects + "/basket.obj --hand pand -o " + out);
  EXPECT_EQ(run.code, 1) << run.out;
  EXPECT_NE(
      run.out.find("hand 'pand' is neither a hand file (URDF or MJCF) nor a bundled hand name"),
      std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("; did you mean 'panda'"), std::string::npos) << run.out;
  run = runTaskmap("hand-info Barrett");
  EXPECT_NE(run.out.find("; did you mean 'barrett'?"), std::string::npos) << run.out;
  run = runTaskmap("hand-info " + kFranka + "x");
  EXPECT_NE(run.out.find("; did you mean '" + kFranka + "'?"), std::string::npos) << run.out;
  run = runTaskmap("hand-info robotiq");
  EXPECT_EQ(run.out.find("did you mean"), std::string::npos) << run.out;
  // Objects: a typo in a path, and a bundled object's name.
  run = runTaskmap("build --object " + objects + "/baskt.obj --hand panda -o " + out);
  EXPECT_EQ(run.code, 1) << run.out;
  EXPECT_NE(run.out.find("cannot open mesh file '" + objects +
                         "/baskt.obj': no such file; did "
                         "you mean '" +
                         objects + "/basket.obj'"),
            std::string::npos)
      << run.out;
  run = runTaskmap("mesh-info baskt");
  EXPECT_EQ(run.code, 1) << run.out;
  EXPECT_NE(run.out.find("cannot open mesh file 'baskt': no such file; did you mean 'basket'?"),
            std::string::npos)
      << run.out;
  EXPECT_FALSE(fs::exists(out));
}

// Bundled objects are named like bundled hands: `--object basket`, `mesh-info mug`.
TEST(HandsCli, BundledObjectsByName) {
  CliRun run = runTaskmap("mesh-info basket --json");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("\"closed\": true"), std::string::npos) << run.out;
  const std::string out = kScratch.path("bundled_box.h5");
  run =
      runTaskmap("build --object box --hand panda --valid 3 --seed 1 --hold-test off -q -o " + out);
  ASSERT_EQ(run.code, 0) << run.out;
  run = runTaskmap("inspect " + out + " --json");
  EXPECT_NE(run.out.find("\"name\": \"box\""), std::string::npos) << run.out;
  // A name is a name only without a folder or an extension: "box.obj" is a file here.
  run = runTaskmap("mesh-info box.obj");
  EXPECT_EQ(run.code, 1) << run.out;
  EXPECT_NE(run.out.find("did you mean"), std::string::npos) << run.out;
}

// `taskmap --help` lists each command in one line; `taskmap CMD --help` keeps the full text.
TEST(CliHelp, EachCommandInOneLine) {
  CliRun run = runTaskmap("--help");
  ASSERT_EQ(run.code, 0) << run.out;
  const std::size_t at = run.out.find("Subcommands:\n");
  ASSERT_NE(at, std::string::npos) << run.out;
  std::istringstream lines(run.out.substr(at + 13));
  std::string line;
  int commands = 0;
  while (std::getline(lines, line) && !line.empty()) {
    EXPECT_LE(line.size(), 100u) << line;
    // "  name   summary": a name, then its summary on the same line, no continuation lines.
    EXPECT_TRUE(line.size() > 14 && line.rfind("  ", 0) == 0 && line[2] != ' ' &&
                line.find_first_not_of(' ', 14) == 14)
        << "not one line per command: '" << line << "'";
    ++commands;
  }
  EXPECT_GE(commands, 15) << run.out;
  run = runTaskmap("build --help");
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_NE(run.out.find("--object"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("bundled object name"), std::string::npos) << run.out;
}

}  // namespace
