#pragma once
// Files a test program writes, and the real inputs it reads: one definition for every test.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>
#include <utility>

namespace taskmap::testing {

/// A directory `<gtest TempDir>/<prefix>_<pid>` for one test program's files, created empty on
/// first use and removed with everything in it when the object is destroyed (at exit for a
/// file-level object, at the end of a test for a fixture member).
class ScratchDir {
 public:
  explicit ScratchDir(std::string prefix) : prefix_(std::move(prefix)) {}
  ~ScratchDir() {
    std::error_code ec;
    if (created_) std::filesystem::remove_all(root_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  /// The directory (created, empty the first time).
  const std::filesystem::path& root() const {
    if (!created_) {
      root_ = std::filesystem::path(::testing::TempDir()) /
              (prefix_ + "_" + std::to_string(::getpid()));
      std::filesystem::remove_all(root_);
      std::filesystem::create_directories(root_);
      created_ = true;
    }
    return root_;
  }
  /// `root()/name` as a string (not created).
  std::string path(const std::string& name) const { return (root() / name).string(); }

 private:
  std::string prefix_;
  mutable std::filesystem::path root_;
  mutable bool created_ = false;
};

#ifdef TEST_DATA_DIR
/// A file of the real input set (tests/data/real, the project's copy of ../shared/real):
/// `realInput("objects/ycb_011_banana.obj")`.
inline std::string realInput(const std::string& relative) {
  return std::string(TEST_DATA_DIR) + "/real/" + relative;
}
#endif

}  // namespace taskmap::testing
