// Hostile inputs (issue 32, label cli): outputs that would destroy an input or a user's file are
// refused, FIFOs and other non-regular inputs are refused without hanging, numeric options
// that wrap or are absurd are refused.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "cli_run.hpp"
#include "hostile_meshes.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

std::string readAll(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class HostileInputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("taskmap_hostile_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fs::copy_file(std::string(TASKMAP_OBJECTS_DIR) + "/box.obj", dir_ / "mybox.obj");
    box_ = readAll(dir_ / "mybox.obj");
  }
  void TearDown() override { fs::remove_all(dir_); }

  // `taskmap <args>` under a 20 s timeout (a hang fails the test instead of blocking it).
  static testing::CliRun taskmap(const std::string& args) {
    return testing::runShell("timeout 20 " + std::string(TASKMAP_BINARY_DIR) + "/bin/taskmap " +
                             args);
  }
  std::string build(const std::string& output, const std::string& more = "") const {
    return "build --object " + (dir_ / "mybox.obj").string() + " --hand panda --valid 5 " +
           "--seed 3 --threads 2 --hold-test off -q -o " + output + more;
  }
  // A small map at dir_/map.h5 (built once per test that needs it).
  void makeMap() const {
    const testing::CliRun r = taskmap(build((dir_ / "map.h5").string()));
    ASSERT_EQ(r.code, 0) << r.out;
  }

  fs::path dir_;
  std::string box_;
};

TEST_F(HostileInputs, BuildRefusesToWriteOverItsObject) {
  const std::string mesh = (dir_ / "mybox.obj").string();
  const testing::CliRun r = taskmap(build(mesh));
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("is the input '" + mesh + "'"), std::string::npos) << r.out;
  EXPECT_EQ(readAll(mesh), box_) << "the user's mesh was replaced";
  // --force never allows it.
  EXPECT_NE(taskmap(build(mesh, " --force")).code, 0);
  EXPECT_EQ(readAll(mesh), box_);
}

TEST_F(HostileInputs, BuildRefusesHardAndSymbolicLinksToItsInputs) {
  fs::create_hard_link(dir_ / "mybox.obj", dir_ / "hard.h5");
  fs::create_symlink(dir_ / "mybox.obj", dir_ / "soft.h5");
  for (const char* name : {"hard.h5", "soft.h5"}) {
    const testing::CliRun r = taskmap(build((dir_ / name).string(), " --force"));
    EXPECT_NE(r.code, 0) << name << ": " << r.out;
    EXPECT_NE(r.out.find("is the input"), std::string::npos) << r.out;
    EXPECT_EQ(readAll(dir_ / name), box_);
  }
  EXPECT_EQ(readAll(dir_ / "mybox.obj"), box_);
  // The hand's URDF and sidecar are inputs too.
  fs::copy(std::string(TASKMAP_HANDS_DIR) + "/panda", dir_ / "hand");
  const std::string urdf = (dir_ / "hand" / "panda.urdf").string();
  const std::string sidecar = (dir_ / "hand" / "panda.hand.json").string();
  const std::string before = readAll(sidecar);
  const testing::CliRun r = taskmap("build --object " + (dir_ / "mybox.obj").string() + " --hand " +
                                    urdf + " --valid 5 --hold-test off -q --force -o " + sidecar);
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_EQ(readAll(sidecar), before);
}

TEST_F(HostileInputs, AnExistingFileThatIsNotAMapNeedsForce) {
  const fs::path notes = dir_ / "notes.h5";
  std::ofstream(notes) << "my notes, not a map\n";
  const testing::CliRun r = taskmap(build(notes.string()));
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("is not a taskmap file"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--force"), std::string::npos) << r.out;
  EXPECT_EQ(readAll(notes), "my notes, not a map\n");
  // An existing map is replaced as before; --force replaces the notes.
  makeMap();
  EXPECT_EQ(taskmap(build((dir_ / "map.h5").string())).code, 0);
  const testing::CliRun forced = taskmap(build(notes.string(), " --force"));
  EXPECT_EQ(forced.code, 0) << forced.out;
  EXPECT_EQ(readAll(notes).rfind("TASKMAP-SEAL ", 0), 0u);
  // A directory is never replaced.
  fs::create_directories(dir_ / "adir");
  EXPECT_NE(taskmap(build((dir_ / "adir").string(), " --force")).code, 0);
}

TEST_F(HostileInputs, ExportImportAndPicturesGuardTheirOutputs) {
  makeMap();
  const std::string map = (dir_ / "map.h5").string();
  const std::string bytes = readAll(map);
  // export onto its own map, in every format.
  for (const char* format : {"ply", "glb", "acronym"}) {
    const testing::CliRun r =
        taskmap("export " + map + " --format " + format + " --force -o " + map);
    EXPECT_NE(r.code, 0) << format << ": " << r.out;
    EXPECT_NE(r.out.find("is the input"), std::string::npos) << r.out;
  }
  EXPECT_EQ(readAll(map), bytes);
  // export over a file of another kind.
  std::ofstream(dir_ / "mesh.ply") << "solid not a ply\n";
  const testing::CliRun ply =
      taskmap("export " + map + " --format ply -o " + (dir_ / "mesh.ply").string());
  EXPECT_NE(ply.code, 0) << ply.out;
  EXPECT_NE(ply.out.find("is not a PLY file"), std::string::npos) << ply.out;
  EXPECT_EQ(
      taskmap("export " + map + " --format ply --force -o " + (dir_ / "mesh.ply").string()).code,
      0);
  // A PLY written by export is replaced without --force.
  EXPECT_EQ(taskmap("export " + map + " --format ply -o " + (dir_ / "mesh.ply").string()).code, 0);
  // import onto its object mesh.
  const testing::CliRun acr =
      taskmap("export " + map + " --format acronym -o " + (dir_ / "grasps.h5").string());
  ASSERT_EQ(acr.code, 0) << acr.out;
  const std::string mesh = (dir_ / "mybox.obj").string();
  const testing::CliRun imp = taskmap("import --acronym " + (dir_ / "grasps.h5").string() +
                                      " --object " + mesh + " --scale 1 --force -o " + mesh);
  EXPECT_NE(imp.code, 0) << imp.out;
  EXPECT_NE(imp.out.find("is the input"), std::string::npos) << imp.out;
  EXPECT_EQ(readAll(mesh), box_);
  // inspect --png over the map itself and over a text file.
  const testing::CliRun png = taskmap("inspect " + map + " --png " + map);
  EXPECT_NE(png.code, 0) << png.out;
  EXPECT_EQ(readAll(map), bytes);
  std::ofstream(dir_ / "pic.png") << "text\n";
  const testing::CliRun text = taskmap("inspect " + map + " --png " + (dir_ / "pic.png").string());
  EXPECT_NE(text.code, 0) << text.out;
  EXPECT_NE(text.out.find("is not a PNG picture"), std::string::npos) << text.out;
}

TEST_F(HostileInputs, DatasetDoesNotReplaceUserFilesInItsDirectory) {
  std::ofstream(dir_ / "list.txt") << "mybox.obj\n";
  fs::create_directories(dir_ / "out");
  std::ofstream(dir_ / "out" / "manifest.json") << "{\"mine\": true}\n";
  const std::string cmd = "dataset --objects " + (dir_ / "list.txt").string() +
                          " --hands panda --valid 5 --seed 1 --hold-test off -q -o " +
                          (dir_ / "out").string();
  const testing::CliRun r = taskmap(cmd);
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("not a taskmap data-set manifest"), std::string::npos) << r.out;
  EXPECT_EQ(readAll(dir_ / "out" / "manifest.json"), "{\"mine\": true}\n");
  fs::remove(dir_ / "out" / "manifest.json");
  std::ofstream(dir_ / "out" / "mybox__panda.h5") << "mine\n";
  const testing::CliRun m = taskmap(cmd);
  EXPECT_NE(m.code, 0) << m.out;
  EXPECT_NE(m.out.find("is not a taskmap file"), std::string::npos) << m.out;
  EXPECT_EQ(readAll(dir_ / "out" / "mybox__panda.h5"), "mine\n");
  EXPECT_EQ(taskmap(cmd + " --force").code, 0);
}

// Every input path that is a FIFO is refused at once, naming the file (none of them may block).
TEST_F(HostileInputs, FifosAreRefusedWithoutHanging) {
  const fs::path fifo_obj = dir_ / "pipe.obj";
  const fs::path fifo_h5 = dir_ / "pipe.h5";
  ASSERT_EQ(::mkfifo(fifo_obj.c_str(), 0600), 0);
  ASSERT_EQ(::mkfifo(fifo_h5.c_str(), 0600), 0);
  fs::copy(std::string(TASKMAP_HANDS_DIR) + "/panda", dir_ / "hand");
  const fs::path urdf_fifo = dir_ / "pipehand.urdf";
  ASSERT_EQ(::mkfifo(urdf_fifo.c_str(), 0600), 0);
  fs::remove(dir_ / "hand" / "panda.hand.json");
  ASSERT_EQ(::mkfifo((dir_ / "hand" / "panda.hand.json").c_str(), 0600), 0);
  std::ofstream(dir_ / "list.txt") << "pipe.obj\n";
  const std::string hand = (dir_ / "hand" / "panda.urdf").string();
  const struct {
    std::string args, file;
  } cases[] = {
      {"mesh-info " + fifo_obj.string(), fifo_obj.string()},
      {"build --object " + fifo_obj.string() + " --hand panda --valid 5 -q -o " +
           (dir_ / "x.h5").string(),
       fifo_obj.string()},
      {"hand-info " + urdf_fifo.string(), urdf_fifo.string()},
      {"hand-info " + hand, (dir_ / "hand" / "panda.hand.json").string()},
      {"inspect " + fifo_h5.string(), fifo_h5.string()},
      {"export " + fifo_h5.string() + " --format ply -o " + (dir_ / "o.ply").string(),
       fifo_h5.string()},
      {"import --acronym " + fifo_h5.string() + " --object " + (dir_ / "mybox.obj").string() +
           " -o " + (dir_ / "i.h5").string(),
       fifo_h5.string()},
      {"dataset --objects " + (dir_ / "list.txt").string() + " --hands panda --valid 5 -o " +
           (dir_ / "ds").string(),
       fifo_obj.string()},
  };
  for (const auto& c : cases) {
    const auto t0 = std::chrono::steady_clock::now();
    const testing::CliRun r = taskmap(c.args);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_NE(r.code, 0) << c.args << "\n" << r.out;
    EXPECT_NE(r.code, 124) << "timed out (blocked on the FIFO): " << c.args;
    EXPECT_LT(s, 10.0) << c.args;
    EXPECT_NE(r.out.find("FIFO"), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.file), std::string::npos) << c.args << "\n" << r.out;
  }
  // The data-set list itself.
  const fs::path list_fifo = dir_ / "pipe.txt";
  ASSERT_EQ(::mkfifo(list_fifo.c_str(), 0600), 0);
  const testing::CliRun list =
      taskmap("dataset --objects " + list_fifo.string() +
              " --hands panda --valid 5 --hold-test off -q -o " + (dir_ / "ds2").string());
  EXPECT_NE(list.code, 0);
  EXPECT_NE(list.code, 124);
  EXPECT_NE(list.out.find("FIFO"), std::string::npos) << list.out;
}

// --trials, --valid, --threads (and taskmap-mpi's --block-trials, same checks in BuildOptions)
// that wrap around or are absurd are refused before any work; a huge budget that is accepted
// costs memory only for the trials that ran.
TEST_F(HostileInputs, NumericOptionsAreCheckedForOverflow) {
  const std::string mesh = (dir_ / "mybox.obj").string();
  const std::string base =
      "build --object " + mesh + " --hand panda -q -o " + (dir_ / "n.h5").string() + " ";
  const struct {
    std::string options, expect;
  } refused[] = {
      {"--trials 18446744073709551615 --valid 5", "at most 10^15"},
      {"--trials 1000000000000001 --valid 5", "at most 10^15"},
      {"--valid 18446744073709551615", "at most 10^15"},
      {"--trials -1 --valid 5", "--trials"},
      {"--valid -5", "--valid"},
      {"--trials 0 --valid 5", "--trials"},
      {"--threads 4294967296 --valid 5", "--threads"},
      {"--threads -1 --valid 5", "--threads"},
      {"--threads 1025 --valid 5", "--threads"},
      {"--trials 99999999999999999999999 --valid 5", "at most 10^15"},  // CLI11 saturates
  };
  for (const auto& c : refused) {
    const testing::CliRun r = taskmap(base + c.options);
    EXPECT_NE(r.code, 0) << c.options << "\n" << r.out;
    EXPECT_NE(r.out.find(c.expect), std::string::npos) << c.options << "\n" << r.out;
    EXPECT_FALSE(fs::exists(dir_ / "n.h5")) << c.options;
  }
  // 2^34 trials: accepted, and under a 1.5 GiB address-space limit (the block table alone once
  // took 2 GiB up front).
  const testing::CliRun big =
      testing::runShell("ulimit -v 1572864; timeout 60 " + std::string(TASKMAP_BINARY_DIR) +
                        "/bin/taskmap " + base + "--trials 17179869184 --valid 5 --threads 2");
  EXPECT_EQ(big.code, 0) << big.out;
  EXPECT_TRUE(fs::exists(dir_ / "n.h5"));
}

// A 3MF that makes assimp abort, and a tiny .x declaring 250M vertices: every entry point
// refuses them with the file named; dataset records them as failed objects and goes on.
TEST_F(HostileInputs, MeshesThatCrashOrExhaustTheParserAreRefused) {
  const std::string bad3mf = (dir_ / "missing.3mf").string();
  ASSERT_TRUE(testing::writeMissingPart3mf(bad3mf));
  const std::string x = (dir_ / "huge.x").string();
  testing::writeHugeDeclarationX(x);
  for (const std::string& mesh : {bad3mf, x}) {
    const auto t0 = std::chrono::steady_clock::now();
    const testing::CliRun info = taskmap("mesh-info " + mesh);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(info.code, 1) << info.out;  // an error, not a signal (-1) or a timeout (124)
    EXPECT_NE(info.out.find(mesh), std::string::npos) << info.out;
    std::printf("mesh-info %s: %.2f s: %s", mesh.c_str(), s, info.out.c_str());
    const testing::CliRun b = taskmap("build --object " + mesh + " --hand panda --valid 5 -q -o " +
                                      (dir_ / "b.h5").string());
    EXPECT_EQ(b.code, 1) << b.out;
  }
  std::ofstream(dir_ / "list.txt") << "mybox.obj\nmissing.3mf\nhuge.x\n";
  const testing::CliRun d =
      taskmap("dataset --objects " + (dir_ / "list.txt").string() +
              " --hands panda --valid 5 --seed 1 --hold-test off -o " + (dir_ / "ds").string());
  EXPECT_EQ(d.code, 1) << d.out;
  EXPECT_NE(d.out.find("2 of 3 jobs failed"), std::string::npos) << d.out;
  EXPECT_NE(d.out.find("mybox.obj x panda: complete"), std::string::npos) << d.out;
}

// A second run on a data-set directory (or a build output) in use refuses, naming the holder.
TEST_F(HostileInputs, SecondRunOnALockedDirectoryRefusesWithTheHolderPid) {
  std::ofstream(dir_ / "list.txt") << "mybox.obj\n";
  fs::create_directories(dir_ / "ds");
  const std::string lock_path = (dir_ / "ds" / ".taskmap-dataset.lock").string();
  const int fd = ::open(lock_path.c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  const std::string pid = std::to_string(::getpid());
  ASSERT_EQ(::write(fd, pid.data(), pid.size()), static_cast<ssize_t>(pid.size()));
  const std::string cmd = "dataset --objects " + (dir_ / "list.txt").string() +
                          " --hands panda --seed 1 --hold-test off -q -o " + (dir_ / "ds").string();
  const testing::CliRun r = taskmap(cmd + " --valid 5");
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("in use by another taskmap run (PID " + pid), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir_ / "ds" / "manifest.json"));
  const std::string out = (dir_ / "locked.h5").string();
  const int bfd = ::open((out + ".lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_EQ(::flock(bfd, LOCK_EX | LOCK_NB), 0);
  const testing::CliRun b = taskmap(build(out));
  EXPECT_NE(b.code, 0) << b.out;
  EXPECT_NE(b.out.find("in use by another taskmap run"), std::string::npos) << b.out;
  ::close(bfd);
  ::close(fd);
  // Free again: two runs with different --valid one after the other; the manifest always
  // describes the files beside it.
  ASSERT_EQ(taskmap(cmd + " --valid 5").code, 0);
  ASSERT_EQ(taskmap(cmd + " --valid 7").code, 0);
  std::ifstream in(dir_ / "ds" / "manifest.json");
  const std::string manifest((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
  EXPECT_NE(manifest.find("\"valid\": 7"), std::string::npos) << manifest;
  const TaskMapData map = readMap((dir_ / "ds" / "mybox__panda.h5").string());
  EXPECT_EQ(std::count(map.grasps.force_closure.begin(), map.grasps.force_closure.end(), 1), 7);
  EXPECT_FALSE(fs::exists(lock_path)) << "the lock file is removed after the run";
}

}  // namespace
}  // namespace taskmap
