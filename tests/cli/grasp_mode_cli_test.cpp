// `taskmap build --grasp / --standoff` and coupled jaws through the CLI (label cli: runs the
// real binary): fingertip grasps of the Robotiq-2F-85-style test hand store no palm contact and
// both jaws; option mistakes exit non-zero with a message naming the option; --sampler antipodal.
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

struct CliRun {
  int exit_code = -1;
  std::string out;  ///< stdout and stderr, merged
};

CliRun runBuild(const std::string& args) {
  const std::string command =
      std::string(TASKMAP_BINARY_DIR) + "/bin/taskmap build " + args + " 2>&1";
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  std::array<char, 4096> buffer;
  std::size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.out.append(buffer.data(), n);
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

const std::string kRobotiq =
    std::string(TEST_DATA_DIR) + "/hands/robotiq_2f85_style/robotiq_2f85_style.urdf";
const std::string kCylinder = std::string(TASKMAP_OBJECTS_DIR) + "/cylinder.obj";

class GraspModeCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("taskmap_grasp_mode_cli_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string out(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;
};

// The hand's sidecar asks for fingertip grasps with a 2 cm standoff: every stored grasp holds
// the can with both pads and no palm contact, and the map records the mode.
TEST_F(GraspModeCli, FingertipGraspsFromTheSidecar) {
  const std::string map_path = out("pinch.h5");
  const CliRun run = runBuild("--object " + kCylinder + " --hand " + kRobotiq + " -o " + map_path +
                              " --valid 40 --trials 1500 --threads 2 --hold-test off --no-cluster");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const TaskMapData map = readMap(map_path);
  const auto params = nlohmann::json::parse(map.sampling.params_json);
  EXPECT_EQ(params.at("grasp_mode"), "fingertip");
  EXPECT_DOUBLE_EQ(params.at("grasp_standoff").get<double>(), 0.02);
  EXPECT_EQ(params.at("centre_coupled"), true);
  ASSERT_GT(map.grasps.size(), 0u) << run.out;
  std::size_t two_jaws = 0;
  for (std::size_t i = 0; i < map.grasps.size(); ++i) {
    std::set<int> links;
    for (auto k = map.grasps.contact_offsets[i]; k < map.grasps.contact_offsets[i + 1]; ++k)
      links.insert(map.grasps.contact_links[static_cast<std::size_t>(k)]);
    EXPECT_EQ(links.count(0), 0u) << "grasp " << i << " touches with the palm (link 0)";
    two_jaws += links.size() == 2;  // left_finger and right_finger
  }
  EXPECT_GE(two_jaws * 10, map.grasps.size() * 9) << two_jaws << " of " << map.grasps.size();
}

// --grasp palm overrides the sidecar; --standoff then is a mistake.
TEST_F(GraspModeCli, OptionsOverrideAndMistakes) {
  const std::string base = "--object " + kCylinder + " --hand " + kRobotiq + " --trials 200 " +
                           "--valid 5 --threads 2 --no-cluster -q -o ";
  const CliRun palm = runBuild(base + out("palm.h5") + " --grasp palm");
  ASSERT_EQ(palm.exit_code, 0) << palm.out;
  EXPECT_EQ(nlohmann::json::parse(readMap(out("palm.h5")).sampling.params_json).at("grasp_mode"),
            "palm");
  const CliRun both = runBuild(base + out("bad.h5") + " --grasp palm --standoff 0.01");
  EXPECT_NE(both.exit_code, 0);
  EXPECT_NE(both.out.find("--standoff applies to fingertip grasps"), std::string::npos) << both.out;
  EXPECT_FALSE(std::filesystem::exists(out("bad.h5")));
  const CliRun mode = runBuild(base + out("bad.h5") + " --grasp pinch");
  EXPECT_NE(mode.exit_code, 0);
  EXPECT_NE(mode.out.find("--grasp"), std::string::npos) << mode.out;
  const CliRun range = runBuild(base + out("bad.h5") + " --grasp fingertip --standoff 2");
  EXPECT_NE(range.exit_code, 0);
  EXPECT_NE(range.out.find("--standoff"), std::string::npos) << range.out;
}

// --sampler antipodal: the jaw hand stores grasps and the map records the sampler and the jaws;
// a three-finger hand is refused with a message naming the sampler, nothing written.
TEST_F(GraspModeCli, AntipodalSamplerIsSelectableAndRecorded) {
  const CliRun run =
      runBuild("--object " + kCylinder + " --hand " + kRobotiq + " -o " + out("anti.h5") +
               " --sampler antipodal --valid 5 --trials 400 --threads 2 --hold-test off "
               "--no-cluster -q");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const TaskMapData map = readMap(out("anti.h5"));
  EXPECT_EQ(map.sampling.sampler, "antipodal");
  const auto params = nlohmann::json::parse(map.sampling.params_json);
  EXPECT_EQ(params.at("sampler"), "antipodal");
  EXPECT_GT(params.at("jaw_open_width").get<double>(), 0.07);
  const CliRun barrett = runBuild("--object " + kCylinder + " --hand barrett -o " + out("bad.h5") +
                                  " --sampler antipodal --valid 5 -q");
  EXPECT_NE(barrett.exit_code, 0);
  EXPECT_NE(barrett.out.find("parallel-jaw hand"), std::string::npos) << barrett.out;
  EXPECT_FALSE(std::filesystem::exists(out("bad.h5")));
}

// --sampler antipodal_palm: the panda (palm grasps) stores grasps, the map records the sampler
// and that the palm was placed; the Robotiq-style hand (fingertip grasps) keeps the pads on the
// pair (place_palm false); a three-finger hand is refused, nothing written.
TEST_F(GraspModeCli, AntipodalPalmSamplerIsSelectableAndRecorded) {
  const CliRun run =
      runBuild("--object " + kCylinder + " --hand panda -o " + out("palm.h5") +
               " --sampler antipodal_palm --valid 5 --trials 400 --threads 2 --hold-test off "
               "--no-cluster -q");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const TaskMapData map = readMap(out("palm.h5"));
  EXPECT_EQ(map.sampling.sampler, "antipodal_palm");
  const auto params = nlohmann::json::parse(map.sampling.params_json);
  EXPECT_EQ(params.at("place_palm"), true);
  const CliRun tip =
      runBuild("--object " + kCylinder + " --hand " + kRobotiq + " -o " + out("tip.h5") +
               " --sampler antipodal_palm --valid 3 --trials 400 --threads 2 --hold-test off "
               "--no-cluster -q");
  ASSERT_EQ(tip.exit_code, 0) << tip.out;
  EXPECT_EQ(nlohmann::json::parse(readMap(out("tip.h5")).sampling.params_json).at("place_palm"),
            false);
  const CliRun barrett = runBuild("--object " + kCylinder + " --hand barrett -o " + out("bad.h5") +
                                  " --sampler antipodal_palm --valid 5 -q");
  EXPECT_NE(barrett.exit_code, 0);
  EXPECT_NE(barrett.out.find("parallel-jaw hand"), std::string::npos) << barrett.out;
  EXPECT_FALSE(std::filesystem::exists(out("bad.h5")));
}

}  // namespace
}  // namespace taskmap
