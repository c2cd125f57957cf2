// taskmap-mpi build against taskmap build (label mpi): the same map for 1-4 ranks and any
// thread count; a rank that dies fails the job with no output file, and the re-run resumes
// from the checkpoint, simulating fewer trials, and gives the same map. Ranks talk over
// loopback TCP (as separate nodes would), oversubscribed on a small machine.
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "map_compare.hpp"
#include "taskmap/mapstore/map_file.hpp"

namespace taskmap {
namespace {

namespace fs = std::filesystem;

struct RunResult {
  int status = -1;  // exit code, or -1 when not exited normally
  std::string output;
};

// Runs a shell command, stdout and stderr together.
RunResult run(const std::string& command) {
  RunResult r;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return r;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
  const int status = ::pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// Maps of schema 2 and later are reproducible byte for byte (no wall-clock time, no HDF5
// object times): compared with cmp. Schema 1 files carry HDF5 object times, so their content
// is compared value by value.
void expectSameMap(const std::string& expected, const std::string& actual) {
  ASSERT_TRUE(fs::exists(actual)) << actual;
  if (kMapSchemaVersion >= 2) {
    EXPECT_EQ(run("cmp " + expected + " " + actual).status, 0) << expected << " vs " << actual;
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
           std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf --valid 60 --seed 3 -o " + out +
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
    EXPECT_EQ(r.status, 0) << r.output;
    reference_simulated_ = std::stoull(capture(r.output, R"(\((\d+) simulated)"));
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
    ASSERT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find(std::to_string(ranks) + " ranks x " + std::to_string(threads)),
              std::string::npos)
        << r.output;
    expectSameMap(ref, out);
    EXPECT_FALSE(fs::exists(out + ".ckpt")) << "checkpoint left behind";
  }
}

TEST_F(MpiBuild, DeadRankFailsTheJobAndTheRerunResumesToTheSameMap) {
  const std::string ref = reference();
  const std::string out = path("resumed.h5");
  // Rank 1 kills itself when handed its third block.
  const RunResult dead =
      run("TASKMAP_MPI_FAULT=1:2 " + mpi(3) + buildArgs(out, 1) + " --block-trials 64 --quiet");
  EXPECT_NE(dead.status, 0) << dead.output;
  EXPECT_FALSE(fs::exists(out)) << "a failed job left an output file";
  ASSERT_TRUE(fs::exists(out + ".ckpt")) << dead.output;

  const RunResult again = run(mpi(2) + buildArgs(out, 1) + " --block-trials 64");
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("resuming from checkpoint"), std::string::npos) << again.output;
  const std::uint64_t now = std::stoull(capture(again.output, R"((\d+) trials simulated now)"));
  EXPECT_LT(now, reference_simulated_) << again.output;
  expectSameMap(ref, out);
  EXPECT_FALSE(fs::exists(out + ".ckpt"));
}

TEST_F(MpiBuild, CheckpointOfOtherOptionsIsNotUsed) {
  const std::string ref = reference();
  const std::string out = path("other.h5");
  const RunResult dead =
      run("TASKMAP_MPI_FAULT=1:1 " + mpi(2) + buildArgs(out, 1) + " --block-trials 64 --quiet");
  EXPECT_NE(dead.status, 0);
  ASSERT_TRUE(fs::exists(out + ".ckpt"));
  // Another block size: the checkpoint's blocks do not fit, the build starts over.
  const RunResult again = run(mpi(2) + buildArgs(out, 1) + " --block-trials 50");
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_NE(again.output.find("belongs to another build"), std::string::npos) << again.output;
  expectSameMap(ref, out);
}

TEST_F(MpiBuild, BadInputIsReportedOnceAndNothingIsWritten) {
  const std::string out = path("bad.h5");
  const std::string missing = path("no_such_object.obj");
  const RunResult r = run(mpi(3) + " build --object " + missing + " --hand " +
                          std::string(TASKMAP_HANDS_DIR) + "/barrett/barrett.urdf -o " + out);
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("taskmap-mpi build: error: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(missing), std::string::npos) << r.output;
  std::size_t errors = 0;
  for (auto at = r.output.find("error"); at != std::string::npos;
       at = r.output.find("error", at + 1))
    ++errors;
  EXPECT_EQ(errors, 1u) << "one rank reports, once:\n" << r.output;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".ckpt"));
}

}  // namespace
}  // namespace taskmap
