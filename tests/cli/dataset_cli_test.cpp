// taskmap dataset (label cli): one map per (object, hand), a bad mesh recorded in the manifest,
// results independent of the list order, re-runs skip verified maps, bad lists refused.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "map_compare.hpp"
#include "taskmap/mapstore/map_file.hpp"
#include "taskmap/meshes/object_model.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class DatasetCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("taskmap_dataset_" + std::to_string(::getpid()));
    fs::create_directories(dir_ / "meshes");
    for (const char* name : {"box.obj", "sphere.obj"})
      fs::copy_file(std::string(TASKMAP_OBJECTS_DIR) + "/" + name, dir_ / "meshes" / name);
    std::ofstream(dir_ / "meshes" / "broken.obj") << "v 0 0 0\nf 1 1 1\n";
    std::ofstream(dir_ / "list.txt") << "meshes/box.obj\n\n# a comment\nmeshes/sphere.obj\n"
                                     << "meshes/broken.obj\n";
    std::ofstream(dir_ / "reversed.txt") << "meshes/broken.obj\nmeshes/sphere.obj\n"
                                         << "meshes/box.obj\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  testing::CliRun dataset(const std::string& list, const std::string& out,
                          const std::string& more = "") const {
    return testing::runShell(
        std::string(TASKMAP_BINARY_DIR) + "/bin/taskmap dataset --objects " +
        (dir_ / list).string() + " --hands " + std::string(TASKMAP_HANDS_DIR) +
        "/panda/panda.urdf --valid 5 --seed 9 --threads 2 --hold-test off -o " +
        (dir_ / out).string() + more);
  }
  json manifest(const std::string& out) const {
    std::ifstream in(dir_ / out / "manifest.json");
    return json::parse(in);
  }

  fs::path dir_;
};

TEST_F(DatasetCli, MapsAndManifestDoNotDependOnTheListOrder) {
  const testing::CliRun a = dataset("list.txt", "a");
  EXPECT_EQ(a.code, 1) << "one mesh is broken:\n" << a.out;
  EXPECT_NE(a.out.find("1 of 3 jobs failed"), std::string::npos) << a.out;
  const json m = manifest("a");
  ASSERT_EQ(m["jobs"].size(), 3u);
  // Sorted by object; paths as written in the list.
  EXPECT_EQ(m["jobs"][0]["object"], "meshes/box.obj");
  EXPECT_EQ(m["jobs"][1]["object"], "meshes/broken.obj");
  EXPECT_EQ(m["jobs"][1]["status"], "failed");
  EXPECT_NE(m["jobs"][1]["error"].get<std::string>().find("broken.obj"), std::string::npos);
  for (const std::size_t i : {std::size_t{0}, std::size_t{2}}) {
    const json& e = m["jobs"][i];
    EXPECT_EQ(e["status"], "complete") << e;
    EXPECT_EQ(e["valid"], 5) << e;
    const std::string map = (dir_ / "a" / e["file"].get<std::string>()).string();
    EXPECT_EQ(e["file_sha256"], sha256File(map));
    const TaskMapData d = readMap(map);
    EXPECT_EQ(d.sampling.seed, e["seed"].get<std::uint64_t>());
    EXPECT_EQ(d.sampling.trials, e["trials"].get<std::uint64_t>());
  }
  EXPECT_NE(m["jobs"][0]["seed"], m["jobs"][2]["seed"]) << "seeds derive from the mesh";

  const testing::CliRun b = dataset("reversed.txt", "b");
  EXPECT_EQ(b.code, 1) << b.out;
  json ma = manifest("a"), mb = manifest("b");
  for (const std::size_t i : {std::size_t{0}, std::size_t{2}}) {
    const std::string file = ma["jobs"][i]["file"];
    testing::expectSameMapContent(readMap((dir_ / "a" / file).string()),
                                  readMap((dir_ / "b" / file).string()));
    if (kMapSchemaVersion < 2) {  // schema 1 maps carry HDF5 object times
      ma["jobs"][i].erase("file_sha256");
      mb["jobs"][i].erase("file_sha256");
    }
  }
  EXPECT_EQ(ma.dump(1), mb.dump(1));
}

TEST_F(DatasetCli, ReRunSkipsVerifiedMapsAndRebuildsChangedOnes) {
  ASSERT_EQ(dataset("list.txt", "a").code, 1);
  const testing::CliRun again = dataset("list.txt", "a");
  EXPECT_NE(again.out.find("2 finished earlier"), std::string::npos) << again.out;
  // Another --valid changes the build parameters: nothing is skipped.
  const testing::CliRun other = testing::runShell(
      std::string(TASKMAP_BINARY_DIR) + "/bin/taskmap dataset --objects " +
      (dir_ / "list.txt").string() + " --hands panda --valid 6 --seed 9 --hold-test off -o " +
      (dir_ / "a").string());
  EXPECT_NE(other.out.find("0 finished earlier"), std::string::npos) << other.out;
  EXPECT_EQ(manifest("a")["jobs"][0]["valid"], 6);
}

TEST_F(DatasetCli, BadListsAreRefused) {
  const testing::CliRun missing = dataset("no_list.txt", "a");
  EXPECT_EQ(missing.code, 1);
  EXPECT_NE(missing.out.find("cannot read object list"), std::string::npos) << missing.out;
  EXPECT_NE(missing.out.find("no_list.txt"), std::string::npos) << missing.out;
  std::ofstream(dir_ / "empty.txt") << "# nothing\n";
  const testing::CliRun empty = dataset("empty.txt", "a");
  EXPECT_NE(empty.out.find("names no mesh"), std::string::npos) << empty.out;
  fs::create_directories(dir_ / "other");
  fs::copy_file(dir_ / "meshes" / "box.obj", dir_ / "other" / "box.obj");
  std::ofstream(dir_ / "clash.txt") << "meshes/box.obj\nother/box.obj\n";
  const testing::CliRun clash = dataset("clash.txt", "a");
  EXPECT_NE(clash.out.find("would both write box__panda.h5"), std::string::npos) << clash.out;
  EXPECT_FALSE(fs::exists(dir_ / "a" / "manifest.json"));
}

TEST_F(DatasetCli, EachObjectTakesItsOwnScale) {
  // The box written in centimetres; the list gives its scale, the sphere takes --scale (1).
  {
    std::ifstream in(dir_ / "meshes" / "box.obj");
    std::ofstream out(dir_ / "meshes" / "box_cm.obj");
    std::string line;
    while (std::getline(in, line)) {
      if (line.rfind("v ", 0) == 0) {
        std::istringstream v(line.substr(2));
        double x = 0, y = 0, z = 0;
        v >> x >> y >> z;
        out << "v " << 100 * x << " " << 100 * y << " " << 100 * z << "\n";
      } else {
        out << line << "\n";
      }
    }
  }
  std::ofstream(dir_ / "scaled.txt") << "meshes/box_cm.obj  0.01\nmeshes/sphere.obj\n";
  const testing::CliRun run = dataset("scaled.txt", "s");
  EXPECT_EQ(run.code, 0) << run.out;
  const json m = manifest("s");
  ASSERT_EQ(m["jobs"].size(), 2u);
  EXPECT_EQ(m["jobs"][0]["object"], "meshes/box_cm.obj");
  EXPECT_EQ(m["jobs"][0]["scale"], 0.01);
  EXPECT_EQ(m["jobs"][0]["status"], "complete") << m["jobs"][0];
  EXPECT_EQ(m["jobs"][1]["scale"], 1.0);
  const TaskMapData box = readMap((dir_ / "s" / "box_cm__panda.h5").string());
  EXPECT_DOUBLE_EQ(box.object.scale, 0.01);
  EXPECT_NE(box.sampling.params_json.find("\"scale\":0.01"), std::string::npos)
      << box.sampling.params_json;
  const TaskMapData sphere = readMap((dir_ / "s" / "sphere__panda.h5").string());
  EXPECT_DOUBLE_EQ(sphere.object.scale, 1.0);
  // Without its scale the centimetre box is refused by the size check, naming the fix.
  std::ofstream(dir_ / "unscaled.txt") << "meshes/box_cm.obj\n";
  const testing::CliRun unscaled = dataset("unscaled.txt", "u");
  EXPECT_EQ(unscaled.code, 1) << unscaled.out;
  const std::string error = manifest("u")["jobs"][0]["error"].get<std::string>();
  EXPECT_NE(error.find("--scale 0.01"), std::string::npos) << error;
  // A scale that is not positive names the line.
  std::ofstream(dir_ / "bad_scale.txt") << "meshes/sphere.obj\nmeshes/box.obj -2\n";
  const testing::CliRun bad = dataset("bad_scale.txt", "b");
  EXPECT_EQ(bad.code, 1) << bad.out;
  EXPECT_NE(bad.out.find("bad_scale.txt' line 2: scale '-2' must be a positive number"),
            std::string::npos)
      << bad.out;
}

}  // namespace
}  // namespace taskmap
