// taskmap-mpi build against taskmap build (label mpi): the same map for 1-4 ranks and any
// thread count; a rank that dies fails the job with no output file, and the re-run resumes
// from the checkpoint, simulating fewer trials, and gives the same map. Ranks talk over
// loopback TCP (as separate nodes would), oversubscribed on a small machine.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_run.hpp"
#include "map_compare.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

using RunResult = testing::CliRun;
RunResult run(const std::string& command) {
  return testing::runShell(command);
}

// Maps of schema 2 and later are reproducible byte for byte (no wall-clock time, no HDF5
// object times): compared with cmp. Schema 1 files carry HDF5 object times, so their content
// is compared value by value.
void expectSameMap(const std::string& expected, const std::string& actual) {
  ASSERT_TRUE(fs::exists(actual)) << actual;
  if (kMapSchemaVersion >= 2) {
    EXPECT_EQ(run("cmp " + expected + " " + actual).code, 0) << expected << " vs " << actual;
  }
  testing::expectSameMapContent(readMap(expected), readMap(actual));
}

class MpiBuild : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("taskmap_mpi_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    ::setenv("SOURCE_DATE_EPOCH", "1700000000", 1);
    // Open MPI refuses to run as root (containers, CI) unless told; no effect otherwise.
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 0);
    ::setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 0);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  // The build arguments of every run: the basket with the three-finger hand, small.
  static std::string buildArgs(const std::string& out, int threads) {
    return " build --object " + std::string(TASKMAP_OBJECTS_DIR) + "/basket.obj --hand " +
           std::string(TASKMAP_HANDS_DIR) +
           "/barrett/barrett.urdf --valid 60 --seed 3 --sampler mixed --hold-test off -o " + out +
           " --threads " + std::to_string(threads);
  }
  static std::string taskmap() { return std::string(TASKMAP_BINARY_DIR) + "/bin/taskmap"; }
  // taskmap-mpi on `ranks` ranks over loopback TCP, blocks of 64 trials.
  static std::string mpi(int ranks) {
    return std::string(TASKMAP_MPIEXEC) + " -n " + std::to_string(ranks) +
           " --oversubscribe --bind-to none --mca btl tcp,self --mca btl_tcp_if_include lo " +
           std::string(TASKMAP_BINARY_DIR) + "/bin/taskmap-mpi";
  }
  std::string reference() {
    const std::string ref = path("reference.h5");
    const RunResult r = run(taskmap() + buildArgs(ref, 2));
    EXPECT_EQ(r.code, 0) << r.out;
    reference_simulated_ = std::stoull(capture(r.out, R"(\((\d+) simulated)"));
    return ref;
  }
  // The first group of the first match of pattern in text ("0" when there is none).
  static std::string capture(const std::string& text, const std::string& pattern) {
    std::smatch m;
    if (std::regex_search(text, m, std::regex(pattern))) return m[1].str();
    ADD_FAILURE() << "no " << pattern << " in\n" << text;
    return "0";
  }

  fs::path dir_;
  std::uint64_t reference_simulated_ = 0;
};

TEST_F(MpiBuild, SameMapAsTaskmapBuildForOneToFourRanks) {
  const std::string ref = reference();
  for (int ranks = 1; ranks <= 4; ++ranks) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks");
    const std::string out = path("mpi" + std::to_string(ranks) + ".h5");
    const int threads = ranks == 1 ? 2 : 1;
    const RunResult r = run(mpi(ranks) + buildArgs(out, threads) + " --block-trials 64");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find(std::to_string(ranks) + " ranks x " + std::to_string(threads)),
              std::string::npos)
        << r.out;
    expectSameMap(ref, out);
    EXPECT_FALSE(fs::exists(out + ".ckpt")) << "checkpoint left behind";
  }
}

// The default build tests each force-closure grasp in physics on the rank that found it: the
// labels travel with the blocks, and two ranks store the map and labels of one process.
TEST_F(MpiBuild, RobustBuildOnTwoRanksIsTheSingleProcessMap) {
  const std::string args = " build --object " + std::string(TASKMAP_OBJECTS_DIR) +
                           "/box.obj --hand " + std::string(TASKMAP_HANDS_DIR) +
                           "/barrett/barrett.urdf --valid 3 --seed 2 --threads 1 -o ";
  const RunResult one = run(taskmap() + args + path("robust1.h5"));
  ASSERT_EQ(one.code, 0) << one.out;
  const RunResult two = run(mpi(2) + args + path("robust2.h5") + " --block-trials 8");
  ASSERT_EQ(two.code, 0) << two.out;
  expectSameMap(path("robust1.h5"), path("robust2.h5"));
  const TaskMapData a = readMap(path("robust1.h5")), b = readMap(path("robust2.h5"));
  ASSERT_TRUE(a.validation && b.validation);
  EXPECT_EQ(a.validation->robustCount(), 3u);
  EXPECT_EQ(a.validation->variant_held, b.validation->variant_held);
  EXPECT_EQ(a.validation->push_translation, b.validation->push_translation);
}

TEST_F(MpiBuild, DeadRankFailsTheJobAndTheRerunResumesToTheSameMap) {
  const std::string ref = reference();
  const std::string out = path("resumed.h5");
  // Rank 1 kills itself when handed its third block.
  const RunResult dead =
      run("TASKMAP_MPI_FAULT=1:2 " + mpi(3) + buildArgs(out, 1) + " --block-trials 64 --quiet");
  EXPECT_NE(dead.code, 0) << dead.out;
  EXPECT_FALSE(fs::exists(out)) << "a failed job left an output file";
  ASSERT_TRUE(fs::exists(out + ".ckpt")) << dead.out;

  const RunResult again = run(mpi(2) + buildArgs(out, 1) + " --block-trials 64");
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_NE(again.out.find("resuming from checkpoint"), std::string::npos) << again.out;
  const std::uint64_t now = std::stoull(capture(again.out, R"((\d+) trials simulated now)"));
  EXPECT_LT(now, reference_simulated_) << again.out;
  expectSameMap(ref, out);
  EXPECT_FALSE(fs::exists(out + ".ckpt"));
}

TEST_F(MpiBuild, CheckpointOfOtherOptionsIsNotUsed) {
  const std::string ref = reference();
  const std::string out = path("other.h5");
  const RunResult dead =
      run("TASKMAP_MPI_FAULT=1:1 " + mpi(2) + buildArgs(out, 1) + " --block-trials 64 --quiet");
  EXPECT_NE(dead.code, 0);
  ASSERT_TRUE(fs::exists(out + ".ckpt"));
  // Another block size: the checkpoint's blocks do not fit, the build starts over.
  const RunResult again = run(mpi(2) + buildArgs(out, 1) + " --block-trials 50");
  ASSERT_EQ(again.code, 0) << again.out;
  EXPECT_NE(again.out.find("belongs to another build"), std::string::npos) << again.out;
  expectSameMap(ref, out);
}

TEST_F(MpiBuild, BadInputIsReportedOnceAndNothingIsWritten) {
  const std::string out = path("bad.h5");
  const std::string missing = path("no_such_object.obj");
  const RunResult r = run(mpi(3) + " build --object " + missing + " --hand " +
                          std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf -o " + out);
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.out.find("taskmap-mpi build: error: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(missing), std::string::npos) << r.out;
  std::size_t errors = 0;
  for (auto at = r.out.find("error"); at != std::string::npos; at = r.out.find("error", at + 1))
    ++errors;
  EXPECT_EQ(errors, 1u) << "one rank reports, once:\n" << r.out;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".ckpt"));
}

// taskmap-mpi build takes the lock of taskmap build on the output: while a taskmap build
// runs on an output, an MPI build of the same output refuses at once naming the holder's PID
// and writes nothing (no checkpoint); once the first run is gone, the output is free again.
TEST_F(MpiBuild, SecondRunOnTheSameOutputRefusesWithTheHolderPid) {
  const std::string out = path("locked.h5");
  const std::string log = path("first.log");
  const std::string first = taskmap() + " build --object " + std::string(TASKMAP_OBJECTS_DIR) +
                            "/basket.obj --hand " + std::string(TASKMAP_HANDS_DIR) +
                            "/barrett/barrett.urdf --valid 100000 --seed 3 --threads 1 -q -o " +
                            out;
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", ("exec " + first + " > " + log + " 2>&1").c_str(), nullptr);
    ::_exit(127);
  }
  // The first run holds the lock once its PID is in the lock file.
  const std::string holder = std::to_string(pid);
  bool held = false;
  for (int i = 0; i < 600 && !held; ++i) {
    std::ifstream in(out + ".lock");
    std::string content;
    held = static_cast<bool>(std::getline(in, content)) && content == holder;
    if (!held) ::usleep(50000);
  }
  ASSERT_TRUE(held) << "taskmap build did not take the lock in 30 s";
  const RunResult second = run(mpi(2) + buildArgs(out, 1) + " --block-trials 64");
  EXPECT_NE(second.code, 0) << second.out;
  EXPECT_NE(second.out.find("output '" + out + "' is in use by another taskmap run (PID " + holder),
            std::string::npos)
      << second.out;
  EXPECT_FALSE(fs::exists(out + ".ckpt")) << "the refused run wrote a checkpoint";
  // Stop the first run and wait for it; the lock goes with the process.
  ::kill(pid, SIGKILL);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  // Free again (a stale lock file is no held lock): the MPI build runs.
  const RunResult third = run(mpi(2) + buildArgs(out, 1) + " --block-trials 64");
  EXPECT_EQ(third.code, 0) << third.out;
}

// A data set of 3 objects (one of them not a mesh) x 2 hands.
class MpiDataset : public MpiBuild {
 protected:
  void SetUp() override {
    MpiBuild::SetUp();
    for (const char* name : {"box.obj", "cylinder.obj"})
      fs::copy_file(std::string(TASKMAP_OBJECTS_DIR) + "/" + name, dir_ / name);
    std::ofstream(dir_ / "broken.obj") << "this is not a mesh\n";
    std::ofstream(dir_ / "list.txt") << "# three objects\nbox.obj\ncylinder.obj\nbroken.obj\n";
    std::ofstream(dir_ / "reversed.txt") << "broken.obj\ncylinder.obj\nbox.obj\n";
  }
  std::string datasetArgs(const std::string& list, const std::string& out) const {
    return " dataset --objects " + path(list) +
           " --hands barrett,panda --valid 10 --seed 4 --hold-test off -o " + path(out) +
           " --threads 1";
  }
  nlohmann::json manifest(const std::string& out) const {
    std::ifstream in(dir_ / out / "manifest.json");
    return nlohmann::json::parse(in);
  }
  // Same manifest; the maps' hashes only where maps are reproducible byte for byte (schema 2).
  void expectSameDataset(const std::string& expected, const std::string& actual) {
    nlohmann::json a = manifest(expected), b = manifest(actual);
    ASSERT_EQ(a["jobs"].size(), 6u);
    ASSERT_EQ(b["jobs"].size(), 6u);
    for (std::size_t i = 0; i < 6; ++i) {
      const nlohmann::json& e = a["jobs"][i];
      SCOPED_TRACE(e.dump());
      if (e["status"] == "complete")
        expectSameMap(path(expected + "/" + e["file"].get<std::string>()),
                      path(actual + "/" + e["file"].get<std::string>()));
      if (kMapSchemaVersion < 2) {
        a["jobs"][i].erase("file_sha256");
        b["jobs"][i].erase("file_sha256");
      }
    }
    EXPECT_EQ(a.dump(1), b.dump(1));
  }
};

TEST_F(MpiDataset, KilledAndResumedDatasetMatchesTheLocalOne) {
  const RunResult local = run(taskmap() + datasetArgs("list.txt", "local"));
  EXPECT_EQ(local.code, 1) << "two jobs have a bad mesh:\n" << local.out;
  const nlohmann::json m = manifest("local");
  std::size_t failed = 0, complete = 0;
  for (const nlohmann::json& e : m["jobs"]) {
    failed += e["status"] == "failed";
    complete += e["status"] == "complete";
    if (e["status"] == "failed") {
      EXPECT_EQ(e["object"], "broken.obj");
      EXPECT_NE(e["error"].get<std::string>().find("broken.obj"), std::string::npos) << e;
    }
  }
  EXPECT_EQ(failed, 2u);
  EXPECT_EQ(complete, 4u);

  // The list in another order, 3 ranks; rank 1 dies when handed its first job.
  const RunResult dead =
      run("TASKMAP_MPI_FAULT=1:0 " + mpi(3) + datasetArgs("reversed.txt", "mpi") + " --quiet");
  EXPECT_NE(dead.code, 0);
  const nlohmann::json killed = manifest("mpi");
  std::size_t pending = 0;
  for (const nlohmann::json& e : killed["jobs"]) pending += e["status"] == "pending";
  EXPECT_GT(pending, 0u) << dead.out << killed.dump(1);

  const RunResult again = run(mpi(2) + datasetArgs("reversed.txt", "mpi"));
  EXPECT_EQ(again.code, 1) << again.out;
  const std::size_t earlier = std::stoul(capture(again.out, R"((\d+) finished earlier)"));
  EXPECT_GE(earlier, 1u) << again.out;
  EXPECT_LE(earlier, 4u - pending) << again.out;
  expectSameDataset("local", "mpi");
  for (const auto& f : fs::directory_iterator(dir_ / "mpi"))
    EXPECT_EQ(f.path().extension() == ".h5" || f.path().filename() == "manifest.json", true)
        << "left behind: " << f.path();
}

TEST_F(MpiDataset, EditedMapIsRebuiltOnReRun) {
  ASSERT_EQ(run(mpi(2) + datasetArgs("list.txt", "set")).code, 1);
  const std::string map = path("set/box__panda.h5");
  ASSERT_TRUE(fs::exists(map));
  { std::ofstream(map, std::ios::app) << "tampered"; }
  const RunResult again = run(mpi(2) + datasetArgs("list.txt", "set"));
  EXPECT_NE(again.out.find("3 finished earlier"), std::string::npos) << again.out;
  EXPECT_NE(again.out.find("box.obj x panda: complete"), std::string::npos) << again.out;
  readMap(map);  // whole again
}

}  // namespace
}  // namespace taskmap
