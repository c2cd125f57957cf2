// `taskmap mesh-info`: exit codes, text and --json output (label cli: runs the real binary).
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

namespace {

struct CliRun {
  int exit_code = -1;
  std::string out;  ///< stdout and stderr, merged
};

CliRun runCli(const std::string& args) {
  const std::string command =
      std::string(TASKMAP_BINARY_DIR) + "/bin/taskmap mesh-info " + args + " 2>&1";
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

std::string object(const std::string& name) {
  return std::string(TASKMAP_OBJECTS_DIR) + "/" + name + ".obj";
}

std::string data(const std::string& name) {
  return std::string(TEST_DATA_DIR) + "/meshes/" + name;
}

TEST(MeshInfoCliTest, TextReportOfAReferenceObject) {
  const CliRun run = runCli(object("box"));
  ASSERT_EQ(run.exit_code, 0) << run.out;
  EXPECT_NE(run.out.find("format:         obj"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("8 vertices, 12 faces, closed"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("repairs:        none"), std::string::npos) << run.out;
  const std::size_t at = run.out.find("volume:");
  ASSERT_NE(at, std::string::npos) << run.out;
  EXPECT_NEAR(std::stod(run.out.substr(at + 7)), 0.06 * 0.08 * 0.12, 1e-10) << run.out;
  EXPECT_NE(run.out.find("torque scale:"), std::string::npos) << run.out;
}

TEST(MeshInfoCliTest, JsonReport) {
  const CliRun run = runCli(object("cylinder") + " --json --scale 2");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j.at("format"), "obj");
  EXPECT_EQ(j.at("closed"), true);
  EXPECT_EQ(j.at("scale"), 2.0);
  EXPECT_TRUE(j.at("repairs").empty());
  EXPECT_EQ(j.at("sha256").get<std::string>().size(), 64u);
  // Volume scales with the cube of the scale: 8 * pi r^2 h within the tessellation error.
  EXPECT_NEAR(j.at("volume").get<double>(), 8 * M_PI * 0.035 * 0.035 * 0.2, 0.005 * 0.0062);
  EXPECT_NEAR(j.at("center_of_mass")[2].get<double>(), 0.2, 1e-6);
  EXPECT_NEAR(j.at("bounds_max")[2].get<double>(), 0.4, 1e-6);
  EXPECT_GT(j.at("torque_scale").get<double>(), 0.2);
}

TEST(MeshInfoCliTest, RepairsAreListed) {
  const CliRun run = runCli(data("cube_inward.obj") + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const auto j = nlohmann::json::parse(run.out);
  ASSERT_EQ(j.at("repairs").size(), 1u);
  EXPECT_EQ(j.at("repairs")[0], "reversed 12 faces to point outward");
  const CliRun strict = runCli(data("cube_inward.obj") + " --no-repair");
  EXPECT_EQ(strict.exit_code, 1) << strict.out;
}

TEST(MeshInfoCliTest, BadInputsExitNonZeroNamingTheFile) {
  for (const std::string name : {"cube_open.obj", "empty.obj", "nan_vertex.obj", "flat.obj",
                                 "malformed.obj", "missing.obj"}) {
    SCOPED_TRACE(name);
    const CliRun run = runCli(data(name));
    EXPECT_EQ(run.exit_code, 1) << run.out;
    EXPECT_NE(run.out.find("taskmap: error: "), std::string::npos) << run.out;
    EXPECT_NE(run.out.find(name), std::string::npos) << run.out;
  }
  const CliRun open = runCli(data("cube_open.obj") + " --json");
  EXPECT_EQ(open.exit_code, 1);
  const auto j = nlohmann::json::parse(open.out.substr(0, open.out.find("taskmap: error")));
  EXPECT_EQ(j.at("closed"), false);
  EXPECT_NE(j.at("error").get<std::string>().find("4 border edges"), std::string::npos);
}

TEST(MeshInfoCliTest, InvalidArguments) {
  EXPECT_NE(runCli("").exit_code, 0);
  EXPECT_NE(runCli(object("box") + " --scale -1").exit_code, 0);
}

}  // namespace
